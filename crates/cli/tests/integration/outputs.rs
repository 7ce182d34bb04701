//! Outputs never destroy inputs: an output that is one of the command's inputs (the mesh, the
//! cage file, the scene, its mesh, a pose file) is refused with status 2 and the input is left
//! byte for byte; a wrong extension or a missing folder is refused before any binding.

use crate::common::{cli, dir, s, stderr};

/// Runs `args`, expects status 2 with `message` on standard error.
fn refused(args: &[&str], message: &str) {
    let out = cli(args);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
    assert!(stderr(&out).contains(message), "{args:?}: {}", stderr(&out));
}

#[test]
fn outputs_that_are_inputs_are_refused_and_the_inputs_stay() {
    let d = dir("outputs");
    let mesh = d.join("box.obj");
    std::fs::write(&mesh, crate::common::BOX_OBJ).unwrap();
    let mesh_before = std::fs::read(&mesh).unwrap();
    // autocage MESH --out MESH (and the mesh renamed to .json, as a hard link to it).
    refused(
        &[
            "autocage",
            s(&mesh),
            "--grid",
            "2",
            "1",
            "1",
            "--out",
            s(&mesh),
        ],
        "--out",
    );
    let alias = d.join("alias.json");
    std::fs::hard_link(&mesh, &alias).unwrap();
    refused(
        &[
            "autocage",
            s(&mesh),
            "--grid",
            "2",
            "1",
            "1",
            "--out",
            s(&alias),
        ],
        "would destroy that input",
    );
    assert_eq!(std::fs::read(&mesh).unwrap(), mesh_before);

    let scene = d.join("scene.json");
    let made = cli(&[
        "autocage",
        s(&mesh),
        "--grid",
        "2",
        "1",
        "1",
        "--out",
        s(&scene),
    ]);
    assert!(made.status.success(), "{}", stderr(&made));
    let scene_before = std::fs::read(&scene).unwrap();
    // cages SCENE --out SCENE: wrong format and its own input.
    refused(&["cages", s(&scene), "--out", s(&scene)], "writes .obj");
    // cages over the scene's mesh file.
    refused(
        &["cages", s(&scene), "--out", s(&mesh)],
        "would destroy that input",
    );
    // new … --cages C --out C.
    let cages = d.join("cages.obj");
    assert!(
        cli(&["cages", s(&scene), "--out", s(&cages)])
            .status
            .success()
    );
    let cages_before = std::fs::read(&cages).unwrap();
    let cages_json = d.join("cages.json");
    std::fs::hard_link(&cages, &cages_json).unwrap();
    refused(
        &[
            "new",
            s(&mesh),
            "--cages",
            s(&cages),
            "--out",
            s(&cages_json),
        ],
        "would destroy that input",
    );
    // deform over its own mesh or its pose file.
    refused(
        &["deform", s(&scene), "--out", s(&mesh)],
        "would destroy that input",
    );
    refused(
        &[
            "deform",
            s(&scene),
            "--pose-file",
            s(&cages),
            "--out",
            s(&cages),
        ],
        "would destroy that input",
    );
    assert_eq!(std::fs::read(&mesh).unwrap(), mesh_before);
    assert_eq!(std::fs::read(&scene).unwrap(), scene_before);
    assert_eq!(std::fs::read(&cages).unwrap(), cages_before);
}

#[test]
fn bad_output_names_are_refused_before_the_work() {
    let d = dir("output-names");
    let scene = d.join("bar.json");
    let demo = cli(&["demo", "bar", "--out", s(&d)]);
    assert!(demo.status.success(), "{}", stderr(&demo));
    // A scene that validates but cannot bind (harmonic cages allowed one solver iteration): a
    // refusal that names the output, not the solver, came before the work.
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
    json["settings"]["harmonic"]["max_iterations"] = serde_json::json!(1);
    for cage in json["cages"].as_array_mut().unwrap() {
        cage["kind"] = serde_json::json!("hc");
    }
    std::fs::write(&scene, json.to_string()).unwrap();
    refused(
        &["deform", s(&scene), "--out", s(&d.join("x.obj"))],
        "did not converge",
    );
    refused(
        &["deform", s(&scene), "--out", s(&d.join("x.stl"))],
        "writes .obj or .glb",
    );
    refused(
        &[
            "deform",
            s(&scene),
            "--out",
            s(&d.join("missing").join("x.obj")),
        ],
        "does not exist",
    );
    refused(
        &["render", s(&scene), "--png", s(&d.join("x.jpg"))],
        "writes .png",
    );
}

#[test]
fn an_edit_that_blows_the_mesh_up_writes_nothing() {
    let d = dir("blow-up");
    assert!(cli(&["demo", "bar", "--out", s(&d)]).status.success());
    let out = d.join("huge.obj");
    let scene = d.join("bar.json");
    let args = [
        "deform",
        s(&scene),
        "--apply",
        "cage_0_0_0: scale 1e300",
        "--out",
        s(&out),
    ];
    // Refused before binding: the edit's pose is beyond the coordinate limit.
    refused(&args, "beyond ±1e9");
    assert!(!out.exists());
}

/// SIGTERM (and Ctrl-C, the same handler) in the middle of a save: the temporary file is
/// removed, the target keeps its old content, and the status says the program was interrupted.
#[cfg(unix)]
#[test]
fn an_interrupted_save_leaves_no_temporary_file_and_the_old_content() {
    use std::time::{Duration, Instant};
    let d = dir("interrupted");
    let target = d.join("bar.json");
    std::fs::write(&target, b"old content").unwrap();
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_starcages-cli"))
        .args(["demo", "bar", "--out", s(&d)])
        // Debug builds only: hold the save with its temporary file created.
        .env("STARCAGES_TEST_SAVE_PAUSE_MS", "20000")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let temporary = || {
        std::fs::read_dir(&d)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with(".bar.json.") && n.ends_with(".starcages-tmp"))
            .collect::<Vec<_>>()
    };
    let start = Instant::now();
    while temporary().is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "no temporary file appeared"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let killed = std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    assert!(stderr(&out).contains("interrupted"), "{}", stderr(&out));
    assert_eq!(temporary(), Vec::<String>::new(), "temporary file left");
    assert_eq!(std::fs::read(&target).unwrap(), b"old content");
}

/// A standard output that cannot be written (a full disk: /dev/full) fails the command with an
/// error naming standard output; a standard error that cannot be written is ignored: the
/// command ends with its own status instead of panicking (exit 101).
#[cfg(target_os = "linux")]
#[test]
fn unwritable_standard_streams_fail_cleanly() {
    use std::process::Stdio;
    let full = || Stdio::from(std::fs::File::create("/dev/full").unwrap());
    let d = dir("streams");
    assert!(cli(&["demo", "bar", "--out", s(&d)]).status.success());
    let scene = d.join("bar.json");
    let run = |args: &[&str], out: Stdio, err: Stdio| {
        std::process::Command::new(env!("CARGO_BIN_EXE_starcages-cli"))
            .args(args)
            .stdout(out)
            .stderr(err)
            .output()
            .unwrap()
    };
    for command in ["info", "validate"] {
        let o = run(&[command, s(&scene)], full(), Stdio::piped());
        assert_eq!(o.status.code(), Some(1), "{command}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("cannot write to standard output"),
            "{command}: {}",
            stderr(&o)
        );
    }
    let o = run(&["info", s(&scene)], Stdio::null(), full());
    assert_eq!(o.status.code(), Some(0));
    let o = run(&["info", s(&d.join("missing.json"))], Stdio::null(), full());
    assert_eq!(o.status.code(), Some(2));
    let out = d.join("out.obj");
    let o = run(
        &["deform", s(&scene), "--out", s(&out), "--stats"],
        Stdio::null(),
        full(),
    );
    assert_eq!(o.status.code(), Some(0));
    assert!(out.exists());
}

/// A write the system refuses (here a file-size limit, which fails the write as a full disk
/// does, with SIGXFSZ ignored as shells do for their children) is not bad input: status 1, a
/// message naming the output, and no partial file; a bad input still exits 2.
#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_exits_1_and_leaves_nothing() {
    let d = dir("full-disk");
    assert!(cli(&["demo", "bar", "--out", s(&d)]).status.success());
    let scene = d.join("bar.json");
    let out = d.join("out.obj");
    let script = format!(
        "trap '' XFSZ; ulimit -f 1; exec '{}' deform '{}' --out '{}'",
        env!("CARGO_BIN_EXE_starcages-cli"),
        s(&scene),
        s(&out)
    );
    let o = std::process::Command::new("sh")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("cannot save"), "{}", stderr(&o));
    assert!(stderr(&o).contains("out.obj"), "{}", stderr(&o));
    assert!(!out.exists());
    let leftovers: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().ends_with(".starcages-tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

/// `bench` and `bench-gpu` moved to `starcages-bench`: the old names say where, with status 2.
#[test]
fn the_old_benchmark_commands_say_where_they_moved() {
    for args in [&["bench", "--json"][..], &["bench-gpu", "--frames", "2"]] {
        let out = cli(args);
        assert_eq!(out.status.code(), Some(2));
        assert!(stderr(&out).contains("starcages-bench"), "{}", stderr(&out));
    }
}
