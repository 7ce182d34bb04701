//! Cage-set OBJ files: each `o`/`g` group is one leaf cage; positions that coincide exactly are
//! welded into one vertex, so neighbouring cages share vertices (and faces) exactly.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;

use super::{FileError, read_obj_cages};
use starcages_core::coords::CoordinateKind;
use starcages_core::scene::{CageSet, LeafCage};

/// Reads an OBJ file of one or more cages into a cage set whose leaf cages all use `kind`.
/// Face vertex indices are welded; vertices used by no face are dropped.
pub fn read_cage_set_obj(path: &Path, kind: CoordinateKind) -> Result<CageSet, FileError> {
    let obj = read_obj_cages(path)?;
    if obj.groups.is_empty() {
        return Err(FileError::parse(
            path,
            1,
            "no faces ('f' lines) in the file; a cage needs faces",
        ));
    }
    // Weld in file order (so a file written by `cage_set_obj_text` reads back with the same
    // vertex order), keeping only vertices that some face uses.
    let mut used = vec![false; obj.positions.len()];
    for v in obj.groups.iter().flat_map(|g| g.faces.iter().flatten()) {
        used[*v as usize] = true;
    }
    let mut welded: HashMap<[u64; 3], u32> = HashMap::new();
    let mut set = CageSet::default();
    let remap: Vec<u32> = obj
        .positions
        .iter()
        .zip(&used)
        .map(|(p, &used)| {
            if !used {
                return u32::MAX;
            }
            let key = (*p + DVec3::ZERO).to_array().map(f64::to_bits);
            *welded.entry(key).or_insert_with(|| {
                set.vertices.push(*p);
                set.vertices.len() as u32 - 1
            })
        })
        .collect();
    let mut names: BTreeMap<String, usize> = BTreeMap::new();
    for group in &obj.groups {
        let faces = group
            .faces
            .iter()
            .map(|face| face.iter().map(|&v| remap[v as usize]).collect())
            .collect();
        // Repeated group names get a numeric suffix so cage names stay unique.
        let count = names.entry(group.name.clone()).or_insert(0);
        let name = if *count == 0 {
            group.name.clone()
        } else {
            format!("{}.{count}", group.name)
        };
        *count += 1;
        set.leaves.push(LeafCage {
            name,
            kind,
            h: None,
            border_h: BTreeMap::new(),
            faces,
        });
    }
    Ok(set)
}

/// OBJ text of the leaf cages at `positions` (one per shared vertex, in the set's order): one
/// `v` line per vertex and one `o` group per cage, so the file reads back with the same
/// vertex order.
pub fn cage_set_obj_text(set: &CageSet, positions: &[DVec3]) -> String {
    let mut s =
        String::from("# StarCages leaf cages: one shared vertex list, one `o` group per cage\n");
    for p in positions {
        writeln!(s, "v {} {} {}", p.x, p.y, p.z).ok();
    }
    for cage in &set.leaves {
        writeln!(s, "o {}", cage.name).ok();
        for face in &cage.faces {
            s.push('f');
            for v in face {
                write!(s, " {}", v + 1).ok();
            }
            s.push('\n');
        }
    }
    s
}

/// Vertex positions of a cage OBJ written by [`cage_set_obj_text`] (or edited elsewhere with
/// its vertex order kept), checked against the expected count.
pub fn read_pose_obj(path: &Path, expected: usize) -> Result<Vec<DVec3>, FileError> {
    let obj = read_obj_cages(path)?;
    if obj.positions.len() != expected {
        return Err(FileError::format(
            path,
            format!(
                "has {} vertices but the scene's cages have {expected}; export the pose with \
                 `starcages-cli cages` and keep its vertex order",
                obj.positions.len()
            ),
        ));
    }
    Ok(obj.positions)
}

#[cfg(test)]
mod tests {
    use super::*;
    use starcages_core::generate::demo::demo_scene;

    #[test]
    fn cage_sets_round_trip_and_shared_vertices_are_welded() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path();
        let scene = demo_scene("egg", 0.2).unwrap();
        let path = dir.join("cages.obj");
        std::fs::write(
            &path,
            cage_set_obj_text(&scene.cages, &scene.cages.vertices),
        )
        .unwrap();
        let back = read_cage_set_obj(&path, CoordinateKind::MeanValue).unwrap();
        assert_eq!(back.vertices, scene.cages.vertices);
        assert_eq!(
            back.leaves.iter().map(|c| &c.faces).collect::<Vec<_>>(),
            scene
                .cages
                .leaves
                .iter()
                .map(|c| &c.faces)
                .collect::<Vec<_>>()
        );
        // Two separately written cubes sharing a face are welded.
        let text = "o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
                    f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n\
                    o b\nv 1 0 0\nv 2 0 0\nv 1 1 0\nv 2 1 0\nv 1 0 1\nv 2 0 1\nv 1 1 1\nv 2 1 1\n\
                    f 9 11 12 10\nf 13 14 16 15\nf 9 10 14 13\nf 11 15 16 12\nf 9 13 15 11\nf 10 12 16 14\n";
        let two = dir.join("two.obj");
        std::fs::write(&two, text).unwrap();
        let set = read_cage_set_obj(&two, CoordinateKind::Green).unwrap();
        assert_eq!(set.vertices.len(), 12);
        assert_eq!(set.adjacency().len(), 1);
        let pose = read_pose_obj(&two, 12).unwrap_err().to_string();
        assert!(
            pose.contains("has 16 vertices but the scene's cages have 12"),
            "{pose}"
        );
    }
}
