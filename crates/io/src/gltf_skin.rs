//! Skinned glTF meshes placed as the specification places them: by their joints, not by the
//! mesh node's transform. Each vertex goes to Σ_k w_k (J_k · IBM_k) v, with J_k the world
//! matrix of joint k in the file's node graph as it stands (the pose the file was saved in: for
//! an export at rest, the bind pose) and IBM_k its inverse bind matrix (glTF 2.0, "Skins").
//! An armature object that is rotated, scaled and moved (FBX-born and Mixamo rigs) then places
//! the mesh where Blender and every engine show it.

use std::path::Path;

use glam::{DAffine3, DMat4};

use super::FileError;
use super::gltf_accessor::{check_accessor, read_elements};

/// World matrix of every node of the document, by node index, through its parents (the node
/// graph as the file stands; a node reached through no parent is a root). A node with several
/// parents (invalid glTF) takes the first. `None` for a node whose parents form a loop (or that
/// hangs below one): it has no world, and a skin that names it is refused. Empty for a
/// document without skins (nothing reads them).
pub(super) fn node_worlds(gltf: &gltf::Gltf) -> Vec<Option<DMat4>> {
    if gltf.skins().next().is_none() {
        return Vec::new();
    }
    let count = gltf.nodes().count();
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for node in gltf.nodes() {
        for child in node.children() {
            if let Some(slot) = parent.get_mut(child.index())
                && slot.is_none()
            {
                *slot = Some(node.index());
            }
        }
    }
    let local: Vec<DMat4> = gltf
        .nodes()
        .map(|n| DMat4::from_cols_array_2d(&n.transform().matrix().map(|c| c.map(f64::from))))
        .collect();
    // Each node's world once, from its nearest ancestor already settled: linear in the nodes
    // whatever the depth (a chain of a million nodes is a valid file).
    let mut world: Vec<Option<Option<DMat4>>> = vec![None; count];
    let mut on_path = vec![false; count];
    let mut path: Vec<usize> = Vec::new();
    for start in 0..count {
        let mut i = start;
        // Up to a settled world, a root, or a node already on this path (a loop).
        let mut above = Some(DMat4::IDENTITY);
        loop {
            if let Some(settled) = world[i] {
                above = settled;
                break;
            }
            if on_path[i] {
                above = None;
                break;
            }
            on_path[i] = true;
            path.push(i);
            match parent[i] {
                Some(p) => i = p,
                None => break,
            }
        }
        for &node in path.iter().rev() {
            above = above.map(|a| a * local[node]);
            world[node] = Some(above);
            on_path[node] = false;
        }
        path.clear();
    }
    world.into_iter().map(Option::flatten).collect()
}

/// Why a placement cannot place a mesh (a matrix that is not finite, or that flattens: scale
/// zero), if it cannot.
pub(super) fn placement_problem(matrix: &DMat4) -> Option<&'static str> {
    if !matrix.is_finite() {
        Some("is not finite (NaN or infinity)")
    } else if DAffine3::from_mat4(*matrix).matrix3.determinant().abs() < f64::MIN_POSITIVE {
        Some("flattens the mesh (a scale of zero)")
    } else {
        None
    }
}

/// The joint matrices J_k · IBM_k of `skin` (IBM the identity where the skin has none), each
/// checked: a joint whose node has no world (its parents form a loop), or whose node's world or
/// inverse bind matrix is not finite or flattens, is refused naming the skin, the joint and
/// its node.
pub(super) fn joint_matrices(
    path: &Path,
    node_names: &[String],
    skin: &gltf::Skin,
    buffers: &[Vec<u8>],
    worlds: &[Option<DMat4>],
) -> Result<Vec<DMat4>, FileError> {
    use gltf::accessor::{DataType as T, Dimensions as D};
    let joints: Vec<usize> = skin.joints().map(|j| j.index()).collect();
    let what = format!(
        "skin {} ('{}')",
        skin.index(),
        skin.name().unwrap_or("unnamed")
    );
    let inverse_bind: Vec<DMat4> = match skin.inverse_bind_matrices() {
        Some(accessor) => {
            let count = check_accessor(
                path,
                &accessor,
                buffers,
                &[(T::F32, D::Mat4)],
                &format!("{what}, inverseBindMatrices"),
            )?;
            if count < joints.len() {
                return Err(FileError::format(
                    path,
                    format!(
                        "{what} has {} joints but {count} inverse bind matrices; re-export the file",
                        joints.len()
                    ),
                ));
            }
            read_elements::<16>(&accessor, buffers, false)
                .iter()
                .map(DMat4::from_cols_array)
                .collect()
        }
        None => vec![DMat4::IDENTITY; joints.len()],
    };
    joints
        .iter()
        .zip(&inverse_bind)
        .enumerate()
        .map(|(k, (&j, ibm))| {
            let node_name = node_names.get(j).map_or("unnamed", String::as_str);
            let joint = format!("{what}, joint {k} (node {j} '{node_name}')");
            let refuse = |why: String| Err(FileError::format(path, format!("{joint} {why}")));
            let Some(world) = worlds.get(j).copied().flatten() else {
                return refuse(
                    "hangs from a loop of parents (a node that is its own ancestor); a glTF \
                     node hierarchy must be a tree: re-export the file"
                        .to_owned(),
                );
            };
            if let Some(why) = placement_problem(&world) {
                return refuse(format!(
                    "stands where its transform (with its parents') {why}; give the joint and \
                     its parents a non-zero scale and re-export"
                ));
            }
            if let Some(why) = placement_problem(ibm) {
                return refuse(format!(
                    "has an inverse bind matrix that {why}; re-export the skin (apply the \
                     armature's scale first)"
                ));
            }
            Ok(world * *ibm)
        })
        .collect()
}

/// The skinning transform of each of a primitive's `count` vertices: Σ_k w_k (J_k · IBM_k)
/// over its JOINTS_n / WEIGHTS_n sets. A vertex whose weights sum to nothing (unweighted) keeps
/// `unweighted` (the mesh node's own placement, as Blender leaves such vertices).
pub(super) fn vertex_transforms(
    path: &Path,
    primitive: &gltf::Primitive,
    buffers: &[Vec<u8>],
    joints: &[DMat4],
    count: usize,
    unweighted: DAffine3,
    what: &dyn Fn(&str) -> String,
) -> Result<Vec<DAffine3>, FileError> {
    use gltf::accessor::{DataType as T, Dimensions as D};
    use gltf::mesh::Semantic;
    let mut sums: Vec<DMat4> = vec![DMat4::ZERO; count];
    let mut totals: Vec<f64> = vec![0.0; count];
    for set in 0.. {
        let (Some(joint_accessor), Some(weight_accessor)) = (
            primitive.get(&Semantic::Joints(set)),
            primitive.get(&Semantic::Weights(set)),
        ) else {
            break;
        };
        let (joint_name, weight_name) = (format!("JOINTS_{set}"), format!("WEIGHTS_{set}"));
        let joint_kinds = [(T::U8, D::Vec4), (T::U16, D::Vec4)];
        let weight_kinds = [(T::F32, D::Vec4), (T::U8, D::Vec4), (T::U16, D::Vec4)];
        let n = check_accessor(
            path,
            &joint_accessor,
            buffers,
            &joint_kinds,
            &what(&joint_name),
        )?;
        let m = check_accessor(
            path,
            &weight_accessor,
            buffers,
            &weight_kinds,
            &what(&weight_name),
        )?;
        if n != count || m != count {
            return Err(FileError::format(
                path,
                format!(
                    "{} and {} have {n} and {m} entries for {count} positions; re-export the file",
                    what(&joint_name),
                    what(&weight_name)
                ),
            ));
        }
        let joint_lists = read_elements::<4>(&joint_accessor, buffers, false);
        let weight_lists = read_elements::<4>(&weight_accessor, buffers, true);
        for (v, (js, ws)) in joint_lists.iter().zip(&weight_lists).enumerate() {
            for (&j, &w) in js.iter().zip(ws) {
                if w == 0.0 {
                    continue;
                }
                let matrix = joints.get(j as usize).ok_or_else(|| {
                    FileError::format(
                        path,
                        format!(
                            "{} names joint {j} at vertex {v}, but the skin has {} joints; \
                             re-export the file",
                            what(&joint_name),
                            joints.len()
                        ),
                    )
                })?;
                if !w.is_finite() || w < 0.0 {
                    return Err(FileError::format(
                        path,
                        format!(
                            "{} holds weight {w} at vertex {v}; weights must be finite and not \
                             negative, re-export the file",
                            what(&weight_name)
                        ),
                    ));
                }
                sums[v] += *matrix * w;
                totals[v] += w;
            }
        }
    }
    sums.iter()
        .zip(&totals)
        .map(|(sum, &total)| {
            if total > 1e-9 {
                // Weights normalised as engines do: the specification asks writers for a sum
                // of 1, and quantised weights miss it by rounding.
                DAffine3::from_mat4(*sum * (1.0 / total))
            } else {
                unweighted
            }
        })
        .zip(&totals)
        .enumerate()
        .map(|(v, (transform, &total))| {
            let Some(why) = placement_problem(&DMat4::from(transform)) else {
                return Ok(transform);
            };
            let reason = if total > 1e-9 {
                format!(
                    "the skin's weighted joint transforms at vertex {v} blend into a transform \
                     that {why}; re-export the skin's weights"
                )
            } else {
                format!(
                    "vertex {v} has no skin weight, so its mesh node places it, and that \
                     node's transform {why}; weight the vertex or fix the node's scale"
                )
            };
            Err(FileError::format(
                path,
                format!("{}: {reason}", what("JOINTS_0/WEIGHTS_0")),
            ))
        })
        .collect()
}
