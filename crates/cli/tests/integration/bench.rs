//! `bench --h`: *Cages at each blending parameter (the paper's Table I), with bind ratios.

use crate::common::{cli, stderr};

#[test]
fn bench_sweeps_h_and_reports_bind_ratios() {
    let out = cli(&[
        "bench", "--only", "bar", "--h", "1.0,0.5", "--no-hc", "--json",
    ]);
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
    let bad = cli(&["bench", "--h", "0"]);
    assert_eq!(bad.status.code(), Some(2));
}
