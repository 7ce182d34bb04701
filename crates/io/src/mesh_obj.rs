//! Mesh OBJ files through `tobj`: every object of the file, triangulated, with normals and
//! texture coordinates when present.

use std::path::Path;

use glam::{DVec3, Vec2, Vec3};

use super::FileError;
use starcages_core::mesh::Mesh;
use starcages_core::mesh::look::MeshLook;

/// Reads all objects of an OBJ file as one mesh.
pub(super) fn read_obj_mesh(path: &Path) -> Result<Mesh, FileError> {
    read_obj(path, false).map(|(mesh, _)| mesh)
}

/// Reads all objects of an OBJ file as one mesh and, when `with_look`, its MTL materials (a
/// missing or broken MTL library is a note of the look).
pub(super) fn read_obj(
    path: &Path,
    with_look: bool,
) -> Result<(Mesh, Option<MeshLook>), FileError> {
    // Without a byte-order mark, which would hide the first line from tobj.
    let text = super::read_text(path)?;
    let text = text.as_str();
    super::obj_lint::check_obj_text(path, text)?;
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut reader = std::io::Cursor::new(text.as_bytes());
    // Materials are not needed for deformation: the .mtl files are read only for the look.
    let folder = path.parent().unwrap_or(Path::new("."));
    let mtl_problem = std::cell::RefCell::new(None::<String>);
    let (models, materials) = tobj::load_obj_buf(&mut reader, &options, |library| {
        if !with_look {
            return Err(tobj::LoadError::GenericFailure);
        }
        let file = super::mesh_look::resolve_beside(folder, &library.to_string_lossy());
        let read = std::fs::File::open(&file)
            .map_err(|e| format!("cannot be read ({e})"))
            .and_then(|f| {
                tobj::load_mtl_buf(&mut std::io::BufReader::new(f))
                    .map_err(|e| format!("is not a readable MTL file ({e})"))
            });
        read.map_err(|why| {
            *mtl_problem.borrow_mut() = Some(format!(
                "{}: its material library {} {why}; the mesh is drawn without its materials",
                path.display(),
                file.display()
            ));
            tobj::LoadError::GenericFailure
        })
    })
    .map_err(|e| {
        FileError::format(
            path,
            format!("not a readable OBJ mesh ({e}); re-export it as OBJ"),
        )
    })?;
    let (mut positions, mut triangles) = (Vec::new(), Vec::new());
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    let (mut all_normals, mut all_uvs) = (true, true);
    for model in &models {
        let m = &model.mesh;
        let base = positions.len() as u32;
        let count = m.positions.len() / 3;
        positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|p| DVec3::new(p[0], p[1], p[2])),
        );
        triangles.extend(
            m.indices
                .chunks_exact(3)
                .map(|t| [t[0] + base, t[1] + base, t[2] + base]),
        );
        all_normals &= m.normals.len() == count * 3;
        all_uvs &= m.texcoords.len() == count * 2;
        normals.extend(
            m.normals
                .chunks_exact(3)
                .map(|n| Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32)),
        );
        uvs.extend(
            m.texcoords
                .chunks_exact(2)
                .map(|t| Vec2::new(t[0] as f32, t[1] as f32)),
        );
    }
    let look = with_look.then(|| {
        let materials = match (materials, mtl_problem.into_inner()) {
            (_, Some(problem)) => Err(problem),
            (Ok(m), None) => Ok(m),
            (Err(e), None) => Err(format!(
                "{}: its materials cannot be read ({e}); the mesh is drawn without them",
                path.display()
            )),
        };
        super::mesh_look::obj_look(path, &models, materials)
    });
    let mesh = super::mesh_from_file(
        path,
        positions,
        triangles,
        all_normals.then_some(normals),
        all_uvs.then_some(uvs),
    )?;
    Ok((mesh, look))
}
