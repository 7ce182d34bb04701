//! A model-based test: long random sequences of commands (moves, gestures, kind and h
//! changes, internal cages added and removed, poses, selection, undo and redo, opening another
//! scene) through the same `apply` the UI uses. After every step the state's invariants hold;
//! at the end, undoing everything gives back the scene as it was opened, exactly.

use std::path::PathBuf;

use glam::DVec3;
use proptest::prelude::*;
use starcages_core::coords::CoordinateKind;
use starcages_core::generate::demo::demo_scene;
use starcages_editor::commands::{CameraChange, UnsavedAnswer};
use starcages_editor::state::undo::Snapshot;
use starcages_editor::state::{EditorState, GestureId, SelectMode};
use starcages_editor::{CageId, Command, Document, EditorApp};
use starcages_io::save_scene;

/// One random step; indices are taken modulo what exists when it runs.
#[derive(Debug, Clone)]
enum Step {
    Move {
        vertex: usize,
        delta: [f64; 3],
    },
    GestureMoves {
        vertex: usize,
        delta: [f64; 3],
        keep: bool,
    },
    Kind {
        cage: usize,
        kind: usize,
    },
    H {
        leaf: usize,
        h: Option<f64>,
    },
    BorderH {
        leaf: usize,
        neighbour: usize,
        h: Option<f64>,
    },
    AddInternal {
        first: usize,
        count: usize,
        kind: usize,
    },
    RemoveInternal {
        cage: usize,
    },
    StorePose {
        name: usize,
    },
    SwitchPose {
        name: Option<usize>,
    },
    DeletePose {
        name: usize,
    },
    Select {
        vertices: Vec<usize>,
        toggle: bool,
    },
    SelectAll,
    Inspect {
        cage: usize,
    },
    Hide {
        cage: usize,
        hidden: bool,
    },
    Hover {
        vertex: usize,
    },
    Frame,
    Undo,
    Redo,
    Wait,
    OpenOther {
        which: usize,
    },
}

const NAMES: [&str; 3] = ["a", "b", "c"];
const KINDS: [CoordinateKind; 3] = [
    CoordinateKind::MeanValue,
    CoordinateKind::Green,
    CoordinateKind::Harmonic,
];

fn delta() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-0.2f64..0.2)
}

fn step() -> impl Strategy<Value = Step> {
    let index = || 0usize..1000;
    prop_oneof![
        6 => (index(), delta()).prop_map(|(vertex, delta)| Step::Move { vertex, delta }),
        3 => (index(), delta(), any::<bool>())
            .prop_map(|(vertex, delta, keep)| Step::GestureMoves { vertex, delta, keep }),
        2 => (index(), 0usize..3).prop_map(|(cage, kind)| Step::Kind { cage, kind }),
        2 => (index(), prop::option::of(0.05f64..1.0)).prop_map(|(leaf, h)| Step::H { leaf, h }),
        1 => (index(), index(), prop::option::of(0.05f64..1.0))
            .prop_map(|(leaf, neighbour, h)| Step::BorderH { leaf, neighbour, h }),
        2 => (index(), 1usize..12, 0usize..3)
            .prop_map(|(first, count, kind)| Step::AddInternal { first, count, kind }),
        2 => index().prop_map(|cage| Step::RemoveInternal { cage }),
        2 => (0usize..3).prop_map(|name| Step::StorePose { name }),
        2 => prop::option::of(0usize..3).prop_map(|name| Step::SwitchPose { name }),
        1 => (0usize..3).prop_map(|name| Step::DeletePose { name }),
        2 => (prop::collection::vec(index(), 0..6), any::<bool>())
            .prop_map(|(vertices, toggle)| Step::Select { vertices, toggle }),
        1 => Just(Step::SelectAll),
        2 => index().prop_map(|cage| Step::Inspect { cage }),
        1 => (index(), any::<bool>()).prop_map(|(cage, hidden)| Step::Hide { cage, hidden }),
        1 => index().prop_map(|vertex| Step::Hover { vertex }),
        1 => Just(Step::Frame),
        5 => Just(Step::Undo),
        3 => Just(Step::Redo),
        2 => Just(Step::Wait),
        1 => (0usize..2).prop_map(|which| Step::OpenOther { which }),
    ]
}

fn cage_ids(state: &EditorState) -> Vec<CageId> {
    CageId::all(&state.doc.scene.cages).collect()
}

fn vertex(state: &EditorState, pick: usize) -> u32 {
    (pick % state.doc.scene.cages.vertices.len().max(1)) as u32
}

/// The commands of one step.
fn commands(state: &EditorState, step: &Step, next_gesture: &mut u64) -> Vec<Command> {
    let scene = &state.doc.scene;
    let moved = |pick: usize, d: &[f64; 3]| {
        let v = vertex(state, pick);
        let to = scene.pose.get(v as usize).copied().unwrap_or_default() + DVec3::from_array(*d);
        (v, to)
    };
    let leaves = scene.cages.leaves.len().max(1);
    match step {
        Step::Move { vertex, delta } => vec![Command::MoveVertices(vec![moved(*vertex, delta)])],
        Step::GestureMoves {
            vertex,
            delta,
            keep,
        } => {
            *next_gesture += 1;
            let half = delta.map(|x| x * 0.5);
            vec![
                Command::BeginGesture {
                    id: GestureId(*next_gesture),
                    label: "drag".into(),
                },
                Command::MoveVertices(vec![moved(*vertex, &half)]),
                Command::MoveVertices(vec![moved(*vertex, delta)]),
                Command::EndGesture { keep: *keep },
            ]
        }
        Step::Kind { cage, kind } => {
            let ids = cage_ids(state);
            match ids.get(cage % ids.len().max(1)) {
                Some(id) => vec![Command::SetCageKind(*id, KINDS[*kind])],
                None => vec![],
            }
        }
        Step::H { leaf, h } => vec![Command::SetCageH {
            leaf: leaf % leaves,
            h: *h,
        }],
        Step::BorderH { leaf, neighbour, h } => {
            let leaf = leaf % leaves;
            let name = scene
                .cages
                .leaves
                .get(neighbour % leaves)
                .map(|c| c.name.clone())
                .unwrap_or_default();
            vec![Command::SetBorderH {
                leaf,
                neighbour: name,
                h: *h,
            }]
        }
        Step::AddInternal { first, count, kind } => {
            let vertices = (0..*count).map(|k| vertex(state, first + k * 7)).collect();
            vec![
                Command::Select {
                    vertices,
                    mode: SelectMode::Replace,
                },
                Command::AddInternalCage(KINDS[*kind]),
            ]
        }
        Step::RemoveInternal { cage } => {
            let count = scene.cages.internals.len();
            if count == 0 {
                return vec![];
            }
            vec![Command::RemoveInternalCage(cage % count)]
        }
        Step::StorePose { name } => vec![Command::StorePose(NAMES[*name].into())],
        Step::SwitchPose { name } => {
            vec![Command::SwitchPose(name.map(|n| NAMES[n].to_owned()))]
        }
        Step::DeletePose { name } => vec![Command::DeletePose(NAMES[*name].into())],
        Step::Select { vertices, toggle } => vec![Command::Select {
            vertices: vertices.iter().map(|&v| vertex(state, v)).collect(),
            mode: if *toggle {
                SelectMode::Toggle
            } else {
                SelectMode::Add
            },
        }],
        Step::SelectAll => vec![Command::SelectAll],
        Step::Inspect { cage } => {
            let ids = cage_ids(state);
            vec![Command::InspectCage(
                ids.get(cage % ids.len().max(1)).copied(),
            )]
        }
        Step::Hide { cage, hidden } => {
            let ids = cage_ids(state);
            match ids.get(cage % ids.len().max(1)) {
                Some(id) => vec![Command::SetCageHidden(*id, *hidden)],
                None => vec![],
            }
        }
        Step::Hover { vertex: v } => vec![Command::Hover(Some(vertex(state, *v)))],
        Step::Frame => vec![Command::Camera(CameraChange::FrameSelection)],
        Step::Undo => vec![Command::Undo],
        Step::Redo => vec![Command::Redo],
        Step::Wait | Step::OpenOther { .. } => vec![],
    }
}

/// Two scenes to open over the edited one, saved in a scratch folder that lives as long as the
/// folder guard.
fn other_scenes() -> (starcages_test_support::Scratch, [PathBuf; 2]) {
    let dir = crate::common::scratch("model");
    let bar = dir.join("bar.json");
    let bumpy = dir.join("bumpy.json");
    save_scene(&demo_scene("bar", 0.3).unwrap(), &bar).unwrap();
    save_scene(&demo_scene("bumpy", 0.3).unwrap(), &bumpy).unwrap();
    (dir, [bar, bumpy])
}

fn run_sequence(steps: &[Step]) -> Result<(), TestCaseError> {
    let doc = Document {
        scene: demo_scene("critter", 0.3).unwrap(),
        path: None,
        dirty: false,
    };
    let mut app = EditorApp::new(doc, None, false);
    app.wait_for_jobs();
    let mut opened = Snapshot::of(&app.state.doc.scene);
    let mut next_gesture = 0;
    let mut poses_changed = 0;
    let mut others = None;
    for (i, step) in steps.iter().enumerate() {
        let pose_before = app.state.doc.scene.pose.clone();
        match step {
            Step::Wait => app.wait_for_jobs(),
            Step::OpenOther { which } => {
                let (_, paths) = others.get_or_insert_with(other_scenes);
                let path = paths[*which].clone();
                crate::common::open_and_answer(
                    &mut app,
                    Command::Open(path),
                    UnsavedAnswer::Discard,
                );
                app.wait_for_jobs();
                opened = Snapshot::of(&app.state.doc.scene);
                prop_assert!(app.state.undo.undo_label().is_none());
            }
            Step::Move { .. } => {
                for command in commands(&app.state, step, &mut next_gesture) {
                    app.run(command.clone());
                    // Moves wait for a structural rebind, as a user would: then they land.
                    if app
                        .state
                        .rig
                        .as_ref()
                        .is_none_or(|r| !r.can_pose(&app.state.doc.scene))
                    {
                        app.wait_for_jobs();
                        app.run(command);
                    }
                }
            }
            _ => {
                for command in commands(&app.state, step, &mut next_gesture) {
                    app.run(command);
                }
            }
        }
        if let Err(e) = app.state.check_invariants() {
            return Err(TestCaseError::fail(format!(
                "after step {i} ({step:?}): {e}"
            )));
        }
        prop_assert!(
            app.state.gesture.is_none(),
            "a gesture was left open at step {}",
            i
        );
        if matches!(step, Step::Move { .. }) && app.state.doc.scene.pose != pose_before {
            poses_changed += 1;
        }
    }
    // The sequence really edited: most moves land (some wait for a bind).
    let moves = steps
        .iter()
        .filter(|s| matches!(s, Step::Move { .. }))
        .count();
    prop_assert!(
        moves == 0 || poses_changed * 3 >= moves,
        "{} of {} moves landed",
        poses_changed,
        moves
    );
    // Undo back to where the document was opened: exactly that scene.
    while app.state.undo.undo_label().is_some() {
        app.run(Command::Undo);
    }
    app.wait_for_jobs();
    prop_assert!(
        Snapshot::of(&app.state.doc.scene) == opened,
        "undo did not restore the scene"
    );
    app.state.check_invariants().map_err(TestCaseError::fail)?;
    // And the binding follows: a fresh one for the restored scene.
    prop_assert!(
        app.state
            .rig
            .as_ref()
            .is_some_and(|r| r.is_current_for(&app.state.doc.scene))
    );
    Ok(())
}

proptest! {
    // 6 sequences of 100 steps: 600 steps a run.
    #![proptest_config(ProptestConfig { cases: 6, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_command_sequences_keep_the_state_valid_and_undo_restores_the_scene(
        steps in prop::collection::vec(step(), 100)
    ) {
        run_sequence(&steps)?;
    }
}
