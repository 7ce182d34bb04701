//! Which way is up in a mesh file. StarCages works Z-up (as Blender); OBJ files are Y-up by
//! convention and glTF files by specification, so a Y-up file is turned on import (a rotation
//! of +90° about X, as Blender's importers do) and turned back on export, and a round trip is
//! the identity.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::mesh::Mesh;

/// The up axis of a mesh file (and of cage and pose OBJ files that go with it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// +Y is up, −Z forward (OBJ convention, glTF specification): turned on import.
    #[default]
    Y,
    /// +Z is up, as StarCages: read as is.
    Z,
}

impl UpAxis {
    /// A point (or direction) of the file in scene coordinates: for Y-up, (x, y, z) → (x, −z, y).
    pub fn to_scene(self, p: DVec3) -> DVec3 {
        match self {
            Self::Y => DVec3::new(p.x, -p.z, p.y),
            Self::Z => p,
        }
    }

    /// A point of the scene in the file's coordinates: the inverse of [`Self::to_scene`].
    pub fn from_scene(self, p: DVec3) -> DVec3 {
        match self {
            Self::Y => DVec3::new(p.x, p.z, -p.y),
            Self::Z => p,
        }
    }

    /// `mesh` (read from a file with this up axis) in scene coordinates: positions and normals
    /// turned; triangles, their order, the weld and UVs unchanged. The turn only swaps and
    /// negates coordinates, so the mesh stays valid and its weld exact (0 and −0 weld alike).
    pub fn mesh_to_scene(self, mesh: Mesh) -> Mesh {
        mesh.with_axes_mapped(|p| self.to_scene(p))
    }

    /// The name used on the command line and in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Y => "y",
            Self::Z => "z",
        }
    }
}

impl std::str::FromStr for UpAxis {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "y" => Ok(Self::Y),
            "z" => Ok(Self::Z),
            _ => Err(format!("'{s}' is not an up axis; use y (OBJ, glTF) or z")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn y_up_turns_up_into_z_and_back() {
        let up = DVec3::Y;
        assert_eq!(UpAxis::Y.to_scene(up), DVec3::Z);
        // Forward (−Z in the file) becomes +Y, Blender's "front" looks along it.
        assert_eq!(UpAxis::Y.to_scene(-DVec3::Z), DVec3::Y);
        let p = DVec3::new(0.1, -2.5, 3.25);
        assert_eq!(UpAxis::Y.from_scene(UpAxis::Y.to_scene(p)), p);
        assert_eq!(UpAxis::Z.to_scene(p), p);
        // A rotation: lengths and handedness kept.
        let (a, b) = (DVec3::X, DVec3::Y);
        let turned = UpAxis::Y.to_scene(a).cross(UpAxis::Y.to_scene(b));
        assert_eq!(turned, UpAxis::Y.to_scene(a.cross(b)));
    }
}
