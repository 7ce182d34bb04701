//! `bench --h`: *Cages at each blending parameter (the paper's Table I), with bind ratios;
//! `bench --scale`: the bind's time and memory against mesh size; `bench --drags`: drags of
//! internal cages.

use crate::common::{bench, demo, dir, ok, s, stderr, stdout};

#[test]
fn bench_sweeps_h_and_reports_bind_ratios() {
    let out = bench(&["--only", "bar", "--h", "1.0,0.5", "--no-hc", "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let methods: Vec<&str> = report["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r["method"].as_str().unwrap())
        .collect();
    assert_eq!(
        methods,
        ["stars h=1", "stars h=0.5", "single-mvc", "single-gc"]
    );
    let ratios = report["ratios"].as_array().unwrap();
    assert_eq!(ratios.len(), 2);
    assert!(
        ratios
            .iter()
            .all(|r| r["bind_vs_mvc"].as_f64().unwrap() > 0.0)
    );
    // h = 1 blends over the whole cage: at least as many weights as h = 0.5.
    let rows = report["rows"].as_array().unwrap();
    let nnz = |i: usize| rows[i]["nonzeros_per_row"].as_f64().unwrap();
    assert!(nnz(0) >= nnz(1), "{} vs {}", nnz(0), nnz(1));
    let bad = bench(&["--h", "0"]);
    assert_eq!(bad.status.code(), Some(2));
    // A misspelt scene is named with the ones there are, not an empty table.
    let unknown = bench(&["--only", "bars", "--json"]);
    assert_eq!(unknown.status.code(), Some(2));
    assert!(
        stderr(&unknown).contains("--only bars: no such scene; the scenes are bar, egg"),
        "{}",
        stderr(&unknown)
    );
}

/// `bench --scale` subdivides a mesh file and reports, per size, the bind's phases and its peak
/// memory within twice what it keeps, and the auto rig's open + rig + bind; bad sizes are
/// refused.
#[test]
fn bench_scale_reports_each_size_s_bind_and_memory() {
    let d = dir("bench-scale");
    let mesh = d.join("tetra.obj");
    // A small closed tetrahedron (Y-up OBJ), grown 1× and 4× by --segments 1,2.
    std::fs::write(
        &mesh,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n",
    )
    .unwrap();
    let out = bench(&[
        "--scale",
        mesh.to_str().unwrap(),
        "--segments",
        "8,16",
        "--json",
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    let sizes: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let sizes = sizes.as_array().unwrap();
    assert_eq!(sizes.len(), 2);
    let triangles: Vec<u64> = sizes
        .iter()
        .map(|s| s["mesh_triangles"].as_u64().unwrap())
        .collect();
    assert_eq!(triangles, [4 * 64, 4 * 256]);
    for size in sizes {
        let stars = &size["stars"];
        assert!(stars["seconds"].as_f64().unwrap() > 0.0);
        assert!(stars["peak_mb"].as_f64().unwrap() > 0.0, "{size}");
        assert!(size["single_mvc"]["seconds"].as_f64().unwrap() > 0.0);
        // The default auto rig of the same mesh: opened, rigged and bound, the total their sum.
        let auto = &size["auto_rig"];
        assert!(auto["leaf_cages"].as_u64().unwrap() >= 1, "{size}");
        let parts: f64 = ["open_seconds", "rig_seconds"]
            .iter()
            .map(|k| auto[k].as_f64().unwrap())
            .sum::<f64>()
            + auto["bind"]["seconds"].as_f64().unwrap();
        assert!(
            (auto["total_seconds"].as_f64().unwrap() - parts).abs() < 1e-9,
            "{size}"
        );
        assert!(size.get("blender").is_none());
    }
    let bad = bench(&["--scale", mesh.to_str().unwrap(), "--segments", "0"]);
    assert_eq!(bad.status.code(), Some(2), "{}", stderr(&bad));
    assert!(stderr(&bad).contains("--segments 0"), "{}", stderr(&bad));
    // A size past the benchmark's bound is refused before any work: 3,000 tetrahedra (12,000
    // triangles) cut 64 ways would be 49 million triangles.
    let fine = d.join("fine.obj");
    let mut text = String::new();
    for k in 0..3000 {
        let (x, b) = (k as f64 * 2.0, 4 * k + 1);
        text.push_str(&format!(
            "v {x} 0 0\nv {} 0 0\nv {x} 1 0\nv {x} 0 1\n",
            x + 1.0
        ));
        let [p, q, r, s] = [b, b + 1, b + 2, b + 3];
        text.push_str(&format!(
            "f {p} {r} {q}\nf {p} {q} {s}\nf {p} {s} {r}\nf {q} {r} {s}\n"
        ));
    }
    std::fs::write(&fine, text).unwrap();
    let huge = bench(&["--scale", fine.to_str().unwrap(), "--segments", "64"]);
    assert_eq!(huge.status.code(), Some(2), "{}", stderr(&huge));
    assert!(
        stderr(&huge).contains("use fewer cuts"),
        "{}",
        stderr(&huge)
    );
}

/// `bench --drags` times a drag of each internal cage of the critter (its right ear made mean
/// value, so that both drags have a driver map) and finds the map's mesh the sparse path's; a
/// scene without internal cages is refused.
#[test]
fn bench_drags_times_each_internal_cage_s_drag_both_ways() {
    let d = dir("bench-drags");
    let path = demo("critter", 0.4, &d);
    let mut scene: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for cage in scene["cages"].as_array_mut().unwrap() {
        if cage["kind"] == "gc" {
            cage["kind"] = "mvc".into();
        }
    }
    std::fs::write(&path, serde_json::to_string(&scene).unwrap()).unwrap();
    let out = bench(&["--drags", s(&path), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let drags = report["drags"].as_array().unwrap();
    let names: Vec<&str> = drags.iter().map(|d| d["cage"].as_str().unwrap()).collect();
    assert_eq!(names, ["ears", "head"]);
    for drag in drags {
        assert!(drag["map_ms"].as_f64().unwrap() > 0.0, "{drag}");
        assert!(drag["map_error"].as_f64().unwrap() < 1e-5, "{drag}");
        assert!(drag["rows"].as_u64().unwrap() > 0, "{drag}");
    }
    let bar = demo("bar", 1.0, &d);
    let bar = bench(&["--drags", s(&bar)]);
    assert_eq!(bar.status.code(), Some(2));
    assert!(
        stderr(&bar).contains("no internal cages"),
        "{}",
        stderr(&bar)
    );
}

/// `bench --rest-edits` edits the bar's leaf-cage vertices one by one and reports, per vertex,
/// its cages, the share of rows bound again and the time split into binding them and the rest;
/// the vertices of both cages (on their shared face) reach every row, a vertex of one cage
/// alone fewer.
#[test]
fn bench_rest_edits_reports_each_vertex_s_reach() {
    let d = dir("bench-rest-edits");
    let bar = demo("bar", 0.3, &d);
    let out = bench(&["--rest-edits", s(&bar), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let edits = report["edits"].as_array().unwrap();
    assert_eq!(
        edits.len(),
        12,
        "the bar's two boxes share 4 of their 12 vertices"
    );
    let rows_of = |cages: usize| -> Vec<f64> {
        edits
            .iter()
            .filter(|e| e["cages"].as_array().unwrap().len() == cages)
            .map(|e| e["rows"].as_f64().unwrap())
            .collect()
    };
    let (shared, own) = (rows_of(2), rows_of(1));
    assert_eq!((shared.len(), own.len()), (4, 8));
    assert!(shared.iter().all(|&r| r > 0.99), "{shared:?}");
    assert!(own.iter().all(|&r| r > 0.0 && r < 0.99), "{own:?}");
    assert!(report["full_bind_s"].as_f64().unwrap() > 0.0);
    // Each edit's time splits into binding its rows and the rest.
    for e in edits {
        let (seconds, rows, other) = (
            e["seconds"].as_f64().unwrap(),
            e["rows_bind_s"].as_f64().unwrap(),
            e["other_s"].as_f64().unwrap(),
        );
        assert!(rows > 0.0 && other > 0.0, "{e}");
        assert!((rows + other - seconds).abs() < 1e-9, "{e}");
    }
    assert!(report["median_other_s"].as_f64().unwrap() > 0.0);
}

#[test]
fn bench_gpu_reports_deformation_and_draw_times() {
    let out = bench(&[
        "gpu", "--detail", "0.4", "--frames", "2", "--width", "160", "--json",
    ]);
    ok(&out);
    let report: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    for key in [
        "gpu_deform_ms",
        "gpu_draw_ms",
        "cpu_deform_ms",
        "triangles",
        "adapter",
    ] {
        assert!(!report[key].is_null(), "{key} missing");
    }
    assert!(report["gpu_deform_ms"].as_f64().unwrap() > 0.0);
}

#[test]
fn absurd_benchmark_sizes_are_refused_at_once() {
    let refused = |args: &[&str], expected: &str| {
        let out = bench(args);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains(expected), "{}", stderr(&out));
    };
    refused(&["--grid", "1000", "1000", "1000"], "1000 is not in 1..=32");
    refused(&["--prism-detail", "1000"], "out of range");
    refused(&["gpu", "--frames", "1000000000"], "not in 1..=10000");
}

/// `--scene --table2` benches a rig of mean value and Green cages (the bumpy demo, written as
/// a scene file) against the single cages of the same kind.
#[test]
fn table_two_pairs_each_kind_with_its_single_cage() {
    let d = dir("table2");
    let scene = d.join("rig.json");
    std::fs::rename(demo("bumpy", 0.2, &d), &scene).unwrap();
    let out = bench(&[
        "--scene",
        s(&scene),
        "--only",
        "rig",
        "--no-hc",
        "--table2",
        "--json",
    ]);
    ok(&out);
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let pairs = report["table2"].as_array().unwrap();
    assert_eq!(pairs.len(), 2);
    assert!(pairs.iter().all(|p| {
        ["memory_ratio", "move_work_ratio"]
            .iter()
            .all(|k| p[k].as_f64().is_some_and(|r| r.is_finite() && r > 0.0))
    }));
}
