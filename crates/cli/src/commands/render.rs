//! `starcages-cli render`: the scene in a pose as a PNG image, rendered offscreen on the GPU
//! (or a software Vulkan driver), with optional influence maps.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use starcages_core::BindControl;
use starcages_core::coords::CoordinateKind;
use starcages_core::star::{StarBinding, single_cage_scene};
use starcages_io::write_atomic;
use starcages_viewport::influence;
use starcages_viewport::offscreen::encode_png;
use starcages_viewport::{
    GpuContext, Layers, Matcap, RenderOptions, Shading, View, framing_camera, render_to_image,
};

use super::pose::PoseArgs;
use crate::InputError;
use crate::progress::with_progress;

/// A standard view.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum ViewArg {
    Front,
    Side,
    Top,
}

/// How the mesh is shaded.
#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
enum ShadingArg {
    /// Studio light on light grey (or the influence map).
    Solid,
    /// The matcap `--matcap` names.
    Matcap,
    /// The mesh file's materials (glTF/GLB, OBJ + MTL, FBX), read with their images.
    Textured,
}

/// A built-in matcap.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum MatcapArg {
    Clay,
    Jade,
    Metal,
    Toon,
}

/// Arguments of `render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file.
    scene: PathBuf,
    #[command(flatten)]
    pose: PoseArgs,
    /// Paint the b map (eq. 11) of one leaf cage, or of `all`.
    #[arg(long, value_name = "CAGE|all", conflicts_with_all = ["join_weight", "difference"])]
    influence: Option<String>,
    /// Paint W(v, p) (eq. 4) of cage vertex V.
    #[arg(long, value_name = "V", conflicts_with = "difference",
        value_parser = clap::value_parser!(u32).range(0..))]
    join_weight: Option<u32>,
    /// Paint the difference to the single-cage deformation of this kind (Fig. 7); prints max
    /// and RMS relative to the bounding box diagonal.
    #[arg(long, value_name = "KIND", value_parser = |s: &str| s.parse::<CoordinateKind>())]
    difference: Option<CoordinateKind>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1024x768", value_parser = parse_size, allow_hyphen_values = true)]
    size: (u32, u32),
    /// Look from a standard view instead of the default three-quarter view.
    #[arg(long, value_enum)]
    view: Option<ViewArg>,
    /// Draw the mesh's edges.
    #[arg(long)]
    wireframe: bool,
    /// Flat shading.
    #[arg(long)]
    flat: bool,
    /// Hide cages and their vertices.
    #[arg(long)]
    no_cages: bool,
    /// Shading: solid, matcap or textured (the mesh file's materials; an influence map is
    /// painted over any of them).
    #[arg(long, value_enum, default_value = "solid")]
    shading: ShadingArg,
    /// The matcap of `--shading matcap`.
    #[arg(long, value_enum, default_value = "clay")]
    matcap: MatcapArg,
    /// The PNG file to write.
    #[arg(long)]
    png: PathBuf,
}

fn parse_size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{text}': write the size as WIDTHxHEIGHT, e.g. 1024x768"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (16..=8192).contains(n))
            .ok_or_else(|| format!("'{text}': each side must be a whole number from 16 to 8192"))
    };
    Ok((parse(w)?, parse(h)?))
}

/// The look of the scene's mesh file with its images decoded; what cannot be used is a note
/// (the image is rendered without it), as in the editor.
fn read_look(
    scene: &starcages_core::scene::Scene,
) -> Option<std::sync::Arc<starcages_core::mesh::look::LoadedLook>> {
    let Some(path) = super::mesh_file(scene) else {
        crate::note!("the scene's mesh is embedded (no mesh file): rendered as Solid");
        return None;
    };
    let look = match starcages_io::read_mesh_look(path) {
        Ok((mesh, _)) if mesh.triangles().len() != scene.mesh.triangles().len() => {
            crate::note!(
                "{}: the file changed since the scene was made ({} triangles, the scene's \
                 mesh has {}); rendered without its materials",
                path.display(),
                mesh.triangles().len(),
                scene.mesh.triangles().len()
            );
            return None;
        }
        Ok((_, look)) => starcages_io::load_look_images(look),
        Err(e) => {
            crate::note!("materials not read: {e}");
            return None;
        }
    };
    for problem in &look.problems {
        crate::note!("{problem}");
    }
    if look.look.is_plain() {
        crate::note!("{}: no materials; rendered as Solid", path.display());
    }
    Some(std::sync::Arc::new(look))
}

/// Runs the command.
pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    let inputs: Vec<&std::path::Path> = std::iter::once(args.scene.as_path())
        .chain(args.pose.pose_file())
        .collect();
    super::check_output("--png", &args.png, &inputs, &["png"])?;
    let super::pose::PosedScene {
        scene,
        cages: mut pose,
        label,
        topology,
        edited,
    } = args.pose.load_posed(&args.scene)?;
    let mesh: Vec<&std::path::Path> = super::mesh_file(&scene).into_iter().collect();
    super::check_output("--png", &args.png, &mesh, &["png"])?;
    let control = BindControl::default();
    let bind = |scene| {
        with_progress("binding", &control, || {
            StarBinding::bind_scene(scene, &control)
        })
        .map_err(|e| InputError(format!("{label}: {e}")))
    };
    let binding = match &topology {
        Some(topology) => with_progress("binding", &control, || {
            StarBinding::bind_scene_with(&scene, topology, &control)
        })
        .map_err(|e| InputError(format!("{label}: {e}")))?,
        None => bind(&scene)?,
    };
    if let Some(hand_moved) = &edited {
        super::pose::keep_joint_volumes(&scene, &binding, &mut pose, hand_moved);
    }
    let map = if let Some(which) = &args.influence {
        let cage = match which.as_str() {
            "all" => None,
            name => Some(scene.cages.leaf_index(name).ok_or_else(|| {
                let names: Vec<&str> = scene.cages.leaves.iter().map(|c| c.name.as_str()).collect();
                InputError(format!(
                    "{label}: no leaf cage named '{name}'; use all or one of: {}",
                    names.join(", ")
                ))
            })?),
        };
        Some(influence::boundary(&binding, cage))
    } else if let Some(v) = args.join_weight {
        if v as usize >= scene.cages.vertices.len() {
            return Err(InputError(format!(
                "{label}: cage vertex {v} does not exist; the scene has {}",
                scene.cages.vertices.len()
            ))
            .into());
        }
        Some(influence::join_weight(&binding, v))
    } else if let Some(kind) = args.difference {
        let single = single_cage_scene(&scene, kind);
        let single_binding = bind(&single)?;
        let a = binding.deform(&scene.cages.vertices, &pose);
        let b = single_binding.deform(&scene.cages.vertices, &pose);
        let (map, stats) = influence::difference(&a, &b);
        crate::note!(
            "difference to single-cage {kind}: max {:.3e}, RMS {:.3e} of the bounding box diagonal",
            stats.max,
            stats.rms
        );
        Some(map)
    } else {
        None
    };
    let gpu = GpuContext::headless()?;
    let mut camera = framing_camera(&scene, &pose);
    if let Some(view) = args.view {
        camera.set_view(match view {
            ViewArg::Front => View::Front,
            ViewArg::Side => View::Side,
            ViewArg::Top => View::Top,
        });
    }
    let look = if args.shading == ShadingArg::Textured {
        read_look(&scene)
    } else {
        None
    };
    let shading = match args.shading {
        ShadingArg::Solid => Shading::Solid,
        ShadingArg::Textured => Shading::Textured,
        ShadingArg::Matcap => Shading::MatCap(match args.matcap {
            MatcapArg::Clay => Matcap::Clay,
            MatcapArg::Jade => Matcap::Jade,
            MatcapArg::Metal => Matcap::Metal,
            MatcapArg::Toon => Matcap::Toon,
        }),
    };
    let options = RenderOptions {
        width: args.size.0,
        height: args.size.1,
        layers: Layers {
            flat: args.flat,
            wireframe: args.wireframe,
            cages: !args.no_cages,
            vertices: !args.no_cages,
            shading,
            vertex_colors: map.is_some(),
            ..Layers::default()
        },
        map,
        look,
        ..RenderOptions::default()
    };
    let image = render_to_image(&gpu, &scene, &binding, &pose, &camera, &options)?;
    write_atomic(&args.png, &encode_png(&image))?;
    crate::output::line(args.png.display())?;
    Ok(())
}
