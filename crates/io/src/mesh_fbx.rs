//! FBX meshes (Maya, Mixamo, Unity, Unreal, Blender), binary and ASCII, read through the
//! `ufbx` crate (the ufbx C library: fuzzed, and bounded here by memory limits).
//!
//! Every mesh node's geometry is placed in world space as Blender's importer shows it: units
//! converted to metres and the file's declared axes to glTF's (+Y up, +Z front, right-handed),
//! so an FBX is Y-up to the rest of StarCages as glTF is. A skinned mesh is placed at its bind
//! pose (the mesh matrix its skin clusters were bound with), so the rest pose is the file's
//! bind pose whatever the armature's current pose. Polygons are triangulated (ufbx's ear
//! clipping); a node whose transform mirrors (negative determinant) has its triangles turned,
//! so the surface stays outward. Per-corner UVs and normals split a vertex only where their
//! values differ (a seam, a hard edge); the mesh welds coincident positions for binding.

use std::path::Path;

use glam::{DAffine3, DMat3, DVec3, Vec2, Vec3};

use super::FileError;
use starcages_core::mesh::Mesh;
use starcages_core::mesh::look::{Material, MeshLook, TextureSource, UvOrigin, display_color};

/// Memory ufbx may use while reading: generous for real files (a 1M-triangle binary FBX of
/// about 60 MB needs a few hundred megabytes), bounded for forged ones (compressed arrays that
/// promise gigabytes).
fn memory_limit(file_bytes: usize) -> usize {
    (64usize << 20).saturating_add(file_bytes.saturating_mul(48))
}

/// What every load of an FBX file here shares: memory bounded by `limit`, FBX only (never
/// guessed from content or name), no animation, embedded or external files.
fn bounded_options(limit: usize) -> ufbx::LoadOpts<'static> {
    let allocator = || ufbx::AllocatorOpts {
        memory_limit: limit,
        ..Default::default()
    };
    ufbx::LoadOpts {
        temp_allocator: allocator(),
        result_allocator: allocator(),
        ignore_animation: true,
        ignore_embedded: true,
        load_external_files: false,
        file_format: ufbx::FileFormat::Fbx,
        no_format_from_content: true,
        no_format_from_extension: true,
        ..Default::default()
    }
}

/// Reads an FBX mesh.
pub(super) fn read_fbx_mesh(path: &Path) -> Result<Mesh, FileError> {
    let bytes = super::read_file_bytes(path)?;
    parse_fbx(path, &bytes)
}

/// Parses the bytes of an FBX file (`path` names it in errors): every mesh node's triangles in
/// world space, metres, +Y up.
pub fn parse_fbx(path: &Path, bytes: &[u8]) -> Result<Mesh, FileError> {
    parse_fbx_with_look(path, bytes, false).map(|(mesh, _)| mesh)
}

/// Reads an FBX mesh and its materials ([`MeshLook`]).
pub(super) fn read_fbx(path: &Path) -> Result<(Mesh, MeshLook), FileError> {
    let bytes = super::read_file_bytes(path)?;
    parse_fbx_with_look(path, &bytes, true)
}

/// Parses an FBX file's meshes and, when `with_look`, keeps the images its materials embed
/// (the materials and each triangle's material are always collected: four bytes a triangle).
fn parse_fbx_with_look(
    path: &Path,
    bytes: &[u8],
    with_look: bool,
) -> Result<(Mesh, MeshLook), FileError> {
    let limit = memory_limit(bytes.len());
    let options = ufbx::LoadOpts {
        target_axes: ufbx::CoordinateAxes::right_handed_y_up(),
        target_unit_meters: 1.0,
        space_conversion: ufbx::SpaceConversion::ModifyGeometry,
        // An attribute index past its array becomes "no index" (checked below, naming the
        // polygon) rather than a silently clamped corner. (ufbx refuses a position index past
        // the vertices itself, without a reason: see `diagnose_geometry`.)
        index_error_handling: ufbx::IndexErrorHandling::NoIndex,
        // Embedded images are kept only for the look (they are inside the file, so within
        // the same memory bound).
        ignore_embedded: !with_look,
        ..bounded_options(limit)
    };
    let scene = ufbx::load_memory(bytes, options).map_err(|error| {
        if error.type_ == ufbx::ErrorType::Unknown
            && let Some(reason) = diagnose_geometry(path, bytes, limit)
        {
            return reason;
        }
        let info = error.info();
        let detail = if info.is_empty() {
            String::new()
        } else {
            format!(": {info}")
        };
        FileError::format(
            path,
            format!(
                "not a readable FBX file ({}{detail}); re-export it from the program that made it",
                &*error.description
            ),
        )
    })?;
    check_unit_scale(path, &scene)?;
    let mut out = Accumulator {
        with_look,
        ..Accumulator::default()
    };
    for node in &scene.nodes {
        if let Some(mesh) = &node.mesh {
            add_node_mesh(path, node, mesh, &mut out)?;
        }
    }
    if out.triangles.is_empty() {
        return Err(FileError::format(
            path,
            if scene.meshes.is_empty() {
                "the file has no mesh (only cameras, lights, bones or empties); export the \
                 mesh objects too"
                    .to_owned()
            } else {
                "the file's meshes have no polygon with three or more corners (only points or \
                 lines); export a surface"
                    .to_owned()
            },
        ));
    }
    let Accumulator {
        positions,
        triangles,
        normals,
        uvs,
        all_normals,
        all_uvs,
        same_position_as,
        mut materials,
        mut triangle_materials,
        notes,
        ..
    } = out;
    let mesh = Mesh::new_with_known_coincident(
        positions,
        triangles,
        all_normals.then_some(normals),
        all_uvs.then_some(uvs),
        Some(same_position_as),
    )
    .map_err(|problem| FileError::InvalidMesh {
        path: path.to_path_buf(),
        problem,
    })?;
    // Triangles without a material wear the default one, last.
    let default = materials.len() as u32;
    for m in &mut triangle_materials {
        if *m == u32::MAX {
            *m = default;
        }
    }
    materials.push(Material::default());
    let look = MeshLook {
        materials,
        triangle_materials,
        uv_origin: UvOrigin::BottomLeft,
        notes,
    };
    Ok((mesh, look))
}

/// Index of `material` in the look, added on first use.
fn material_index(path: &Path, material: &ufbx::Material, out: &mut Accumulator) -> u32 {
    if let Some(&i) = out.material_of_element.get(&material.element.element_id) {
        return i;
    }
    // The PBR base colour where the file has one, else the classic diffuse colour × factor.
    let (map, factor) = if material.pbr.base_color.has_value {
        (
            &material.pbr.base_color,
            material.pbr.base_factor.value_vec4.x,
        )
    } else {
        (
            &material.fbx.diffuse_color,
            material.fbx.diffuse_factor.value_vec4.x,
        )
    };
    let factor = if factor > 0.0 { factor } else { 1.0 };
    let colour = if map.has_value {
        let v = &map.value_vec4;
        [v.x * factor, v.y * factor, v.z * factor, 1.0].map(|c| c as f32)
    } else {
        [1.0; 4]
    };
    let name = material.element.name.to_string();
    let texture = map
        .texture
        .as_ref()
        .or(material.fbx.diffuse_color.texture.as_ref())
        .and_then(|texture| {
            if !texture.content.is_empty() {
                return out.with_look.then(|| TextureSource::Embedded {
                    name: format!(
                        "texture '{}' of material '{name}' in {}",
                        texture.element.name,
                        path.display()
                    ),
                    bytes: std::sync::Arc::new(texture.content.to_vec()),
                });
            }
            let folder = path.parent().unwrap_or(Path::new("."));
            // ufbx resolves the relative name against the file's folder; an absolute name
            // from the artist's machine is tried where it points, then beside the file.
            let relative = texture.relative_filename.to_string();
            let absolute = texture.absolute_filename.to_string();
            let beside = |name: &str| super::mesh_look::resolve_beside(folder, name);
            let candidates = [
                (!relative.is_empty()).then(|| beside(&relative)),
                (!absolute.is_empty()).then(|| std::path::PathBuf::from(&absolute)),
                Path::new(&absolute.replace('\\', "/"))
                    .file_name()
                    .map(|n| folder.join(n)),
            ];
            let found = candidates.iter().flatten().find(|p| p.is_file()).cloned();
            match found.or_else(|| candidates.into_iter().flatten().next()) {
                Some(file) => Some(TextureSource::File(file)),
                None => {
                    out.notes.push(format!(
                        "{}: material '{name}' has a texture without a file name; it is drawn \
                         without its image",
                        path.display()
                    ));
                    None
                }
            }
        });
    let index = out.materials.len() as u32;
    out.materials.push(Material {
        name,
        base_color: display_color(colour),
        texture,
    });
    out.material_of_element
        .insert(material.element.element_id, index);
    index
}

/// Why ufbx failed without a reason (its "Failed to load"), when the file's structure reads
/// without its geometry: then a mesh's geometry is what is broken. ufbx refuses a polygon
/// that names a vertex past the mesh's vertex list this way, and skips the arrays when asked to
/// ignore geometry, so the meshes are named and the likely reasons given.
fn diagnose_geometry(path: &Path, bytes: &[u8], limit: usize) -> Option<FileError> {
    let options = ufbx::LoadOpts {
        ignore_geometry: true,
        retain_dom: true,
        ..bounded_options(limit)
    };
    let scene = ufbx::load_memory(bytes, options).ok()?;
    let root = scene.dom_root.as_ref()?;
    let objects = root.children.iter().find(|c| &*c.name == "Objects")?;
    let names: Vec<String> = objects
        .children
        .iter()
        .filter(|c| &*c.name == "Geometry")
        .map(|geometry| {
            // "Geometry::name" in ASCII files, "name\0\x01Geometry" in binary ones (the raw
            // bytes: ufbx keeps the string in the blob).
            let raw = geometry
                .values
                .get(1)
                .map(|v| String::from_utf8_lossy(&v.value_blob).into_owned())
                .unwrap_or_default();
            let name = raw
                .strip_prefix("Geometry::")
                .unwrap_or_else(|| raw.split('\0').next().unwrap_or(""));
            format!("'{name}'")
        })
        .collect();
    let meshes = match names.len() {
        0 => return None,
        1 => format!("mesh {}", names[0]),
        _ => format!("one of the meshes {}", names.join(", ")),
    };
    Some(FileError::format(
        path,
        format!(
            "the file's nodes read, but the geometry of {meshes} does not: a polygon names a \
             vertex past the mesh's vertex list, or an array is cut short (the FBX reader gives \
             no further reason); the file is damaged: re-export it"
        ),
    ))
}

/// Refuses a unit scale that is zero, negative or not finite: Blender's importer scales the
/// mesh by it (to nothing, or mirrored), ufbx falls back to centimetres (100× too large);
/// either way the mesh is not the one the file's author saw.
fn check_unit_scale(path: &Path, scene: &ufbx::Scene) -> Result<(), FileError> {
    let Some(unit) = ufbx::find_prop(&scene.settings.props, "UnitScaleFactor") else {
        return Ok(());
    };
    let centimetres = unit.value_vec4.x;
    if centimetres.is_finite() && centimetres > 0.0 {
        return Ok(());
    }
    Err(FileError::format(
        path,
        format!(
            "GlobalSettings: UnitScaleFactor is {centimetres} (centimetres per unit); it must \
             be a positive number (1 for centimetres, 100 for metres): set the scene's unit in \
             the program that made the file and export again"
        ),
    ))
}

/// The triangles of every node read so far, with one vertex per distinct (position, normal,
/// UV) corner of each node.
#[derive(Default)]
struct Accumulator {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    normals: Vec<Vec3>,
    uvs: Vec<Vec2>,
    /// Whether every node so far had normals (resp. UVs); otherwise none are kept.
    all_normals: bool,
    all_uvs: bool,
    /// Mesh nodes read so far.
    nodes: usize,
    /// Per vertex, the first vertex made from the same position of the same node (itself
    /// for the first): known coincident, so welding need not sort them.
    same_position_as: Vec<u32>,
    /// Whether embedded images are kept (they can be large).
    with_look: bool,
    /// The materials met so far, and each one's index by ufbx element id.
    materials: Vec<Material>,
    material_of_element: std::collections::HashMap<u32, u32>,
    /// Per triangle, its material (`u32::MAX`: none, the default one once all are known).
    triangle_materials: Vec<u32>,
    /// What of the materials could not be used.
    notes: Vec<String>,
}

/// Adds one node's instance of `mesh`, placed in world space.
fn add_node_mesh(
    path: &Path,
    node: &ufbx::Node,
    mesh: &ufbx::Mesh,
    out: &mut Accumulator,
) -> Result<(), FileError> {
    // A skinned mesh rests where its clusters were bound (FBX's bind pose: the bone's world
    // matrix then, times the geometry's matrix relative to it), not where its node or its bones
    // stand now (ufbx's `geometry_to_world` of a cluster follows the bone's current pose).
    let bound = mesh.skin_deformers.iter().find_map(|skin| {
        skin.clusters
            .iter()
            .next()
            .map(|c| affine(&c.bind_to_world) * affine(&c.geometry_to_bone))
    });
    let world = bound.unwrap_or_else(|| affine(&node.geometry_to_world));
    let name = &*node.element.name;
    if !world.is_finite() || world.matrix3.determinant() == 0.0 {
        return Err(FileError::format(
            path,
            format!(
                "node '{name}' has a transform that is not finite or flattens its mesh \
                 (scale 0); fix the node's scale and re-export"
            ),
        ));
    }
    let mirrored = world.matrix3.determinant() < 0.0;
    let normal_matrix = world.matrix3.inverse().transpose();
    let has_normals = mesh.vertex_normal.exists;
    let has_uvs = mesh.vertex_uv.exists;
    out.all_normals = has_normals && (out.all_normals || out.nodes == 0);
    out.all_uvs = has_uvs && (out.all_uvs || out.nodes == 0);
    out.nodes += 1;

    // Every attribute's index of every corner, checked once.
    let corners = mesh.num_indices;
    let indices = |attribute, values, what| {
        checked_indices(path, name, &mesh.faces, attribute, corners, values, what)
    };
    let positions = &mesh.vertex_position.values;
    let position_of = indices(&mesh.vertex_position.indices, positions.len(), "vertex")?;
    // Absent attributes read as no indices (every corner gets the default value).
    let normal_of = if has_normals {
        indices(
            &mesh.vertex_normal.indices,
            mesh.vertex_normal.values.len(),
            "normal",
        )?
    } else {
        &[]
    };
    let uv_of = if has_uvs {
        indices(&mesh.vertex_uv.indices, mesh.vertex_uv.values.len(), "UV")?
    } else {
        &[]
    };
    let normal = |corner: usize| {
        let n = (normal_of.get(corner)).and_then(|&i| mesh.vertex_normal.values.get(i as usize));
        n.map_or([0.0; 3], |n| [n.x, n.y, n.z])
    };
    let uv = |corner: usize| {
        let t = (uv_of.get(corner)).and_then(|&i| mesh.vertex_uv.values.get(i as usize));
        t.map_or([0.0; 2], |t| [t.x, t.y])
    };

    // The corners of polygons with a surface (three or more corners), grouped by position.
    let mut used = vec![false; corners];
    for face in mesh.faces.iter().filter(|f| f.num_indices >= 3) {
        let range = face.index_begin as usize..(face.index_begin + face.num_indices) as usize;
        used.get_mut(range)
            .into_iter()
            .flatten()
            .for_each(|u| *u = true);
    }
    let mut first_of_position = vec![0u32; positions.len() + 1];
    for c in (0..corners).filter(|&c| used[c]) {
        first_of_position[position_of[c] as usize + 1] += 1;
    }
    for p in 0..positions.len() {
        first_of_position[p + 1] += first_of_position[p];
    }
    let mut next = first_of_position.clone();
    let mut by_position = vec![0u32; first_of_position[positions.len()] as usize];
    for c in (0..corners).filter(|&c| used[c]) {
        let slot = &mut next[position_of[c] as usize];
        by_position[*slot as usize] = c as u32;
        *slot += 1;
    }

    // One vertex per distinct (position, normal, UV): exporters write normals per polygon
    // corner, so a position's corners are matched by value (a seam or a hard edge splits it).
    // Vertices follow the file's position order.
    let mut vertex_of_corner = vec![u32::MAX; corners];
    let mut distinct: Vec<([f64; 3], [f64; 2], u32)> = Vec::new();
    for p in 0..positions.len() {
        let group = &by_position[first_of_position[p] as usize..first_of_position[p + 1] as usize];
        distinct.clear();
        let representative = out.positions.len() as u32;
        for &c in group {
            let c = c as usize;
            let (n, t) = (normal(c), uv(c));
            if let Some(&(_, _, v)) = distinct.iter().find(|(dn, dt, _)| *dn == n && *dt == t) {
                vertex_of_corner[c] = v;
                continue;
            }
            let v = u32::try_from(out.positions.len()).map_err(|_| {
                FileError::format(path, "more than 4 billion vertices; split the file")
            })?;
            let at = positions[p];
            out.positions
                .push(world.transform_point3(DVec3::new(at.x, at.y, at.z)));
            if has_normals {
                let turned = (normal_matrix * DVec3::from_array(n)).normalize_or_zero();
                out.normals.push(turned.as_vec3());
            }
            if has_uvs {
                out.uvs.push(Vec2::new(t[0] as f32, t[1] as f32));
            }
            out.same_position_as.push(representative);
            distinct.push((n, t, v));
            vertex_of_corner[c] = v;
        }
    }

    // Each of the mesh's material slots in the look.
    let slots: Vec<u32> = mesh
        .materials
        .iter()
        .map(|m| material_index(path, m, out))
        .collect();
    // Triangles: a polygon of more than three corners by ufbx's ear clipping.
    let mut fan: Vec<u32> = Vec::new();
    for (face_index, face) in mesh.faces.iter().enumerate() {
        if face.num_indices < 3 {
            continue;
        }
        let material = (mesh.face_material.get(face_index))
            .and_then(|&slot| slots.get(slot as usize))
            .or(slots.first())
            .copied()
            .unwrap_or(u32::MAX);
        let count = if face.num_indices == 3 {
            fan.clear();
            fan.extend(face.index_begin..face.index_begin + 3);
            1
        } else {
            fan.resize((face.num_indices as usize - 2) * 3, 0);
            ufbx::triangulate_face(&mut fan, mesh, *face) as usize
        };
        for triangle in fan.chunks_exact(3).take(count) {
            let [a, b, c] = [triangle[0], triangle[1], triangle[2]].map(|corner| {
                vertex_of_corner
                    .get(corner as usize)
                    .copied()
                    .unwrap_or(u32::MAX)
            });
            if [a, b, c].contains(&u32::MAX) {
                return Err(FileError::format(
                    path,
                    format!(
                        "mesh of node '{name}': a polygon names a corner it does not have; re-export the file"
                    ),
                ));
            }
            out.triangles
                .push(if mirrored { [a, c, b] } else { [a, b, c] });
            out.triangle_materials.push(material);
        }
    }
    Ok(())
}

/// The first `corners` indices of an attribute, each checked against its `values`: borrowed
/// from the file's arrays, or an error naming the node and the attribute.
fn checked_indices<'a>(
    path: &Path,
    node: &str,
    faces: &[ufbx::Face],
    attribute: &'a [u32],
    corners: usize,
    values: usize,
    what: &str,
) -> Result<&'a [u32], FileError> {
    let indices = attribute.get(..corners).ok_or_else(|| {
        FileError::format(
            path,
            format!(
                "mesh of node '{node}': {} {what} indices for {corners} polygon corners; \
                 re-export the file",
                attribute.len()
            ),
        )
    })?;
    if let Some(corner) = indices.iter().position(|&i| i as usize >= values) {
        let polygon = faces
            .iter()
            .position(|f| (f.index_begin..f.index_begin + f.num_indices).contains(&(corner as u32)))
            .map_or_else(|| "a polygon".to_owned(), |f| format!("polygon {f}"));
        let named = match indices[corner] {
            u32::MAX => format!("a {what} past the mesh's {values}"),
            index => format!("{what} {index}, but the mesh has {values}"),
        };
        return Err(FileError::format(
            path,
            format!(
                "mesh of node '{node}': {polygon} names {named} (corner {corner}, counted \
                 from 0); the file is damaged: re-export it"
            ),
        ));
    }
    Ok(indices)
}

/// An FBX matrix (column-major 3×4) as an affine map.
fn affine(m: &ufbx::Matrix) -> DAffine3 {
    DAffine3 {
        matrix3: DMat3::from_cols(
            DVec3::new(m.m00, m.m10, m.m20),
            DVec3::new(m.m01, m.m11, m.m21),
            DVec3::new(m.m02, m.m12, m.m22),
        ),
        translation: DVec3::new(m.m03, m.m13, m.m23),
    }
}
