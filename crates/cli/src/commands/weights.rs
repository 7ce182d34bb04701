//! `starcages-cli weights`: coordinates of points with respect to one cage.
//!
//! Output (documented in docs/cli.md): `{"kind", "vertices", "faces", "polygons", "points"}`
//! where each point is `{"w": [...]}` (MVC, HC: over the cage's vertices in file order) or
//! `{"phi": [...], "psi": [...]}` (GC: φ over vertices, ψ over triangles in file order after
//! fan triangulation of polygons).

use std::io::{BufWriter, Write as _};
use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use serde::Serialize;
use starcages_core::coords::HarmonicSettings;
use starcages_core::{BindControl, BindSettings, CageWeights, CoordError, CoordinateKind, bind};
use starcages_io::{read_cage_obj, read_points};

use crate::InputError;
use crate::progress::with_progress;

/// Arguments of `weights`.
#[derive(Debug, Args)]
pub struct WeightsArgs {
    /// Cage OBJ file (one closed, outward-oriented cage; polygons are fan-triangulated).
    #[arg(long)]
    cage: PathBuf,
    /// Points file: one `x y z` per line; blank lines and `#` comments allowed.
    #[arg(long)]
    points: PathBuf,
    /// Coordinate system: mvc, hc or gc.
    #[arg(long, value_parser = parse_kind)]
    coords: CoordinateKind,
    /// Harmonic coordinates: grid cells along the cage's longest side.
    #[arg(long, default_value_t = HarmonicSettings::default().resolution,
        value_parser = clap::value_parser!(u32).range(0..))]
    resolution: u32,
}

fn parse_kind(s: &str) -> Result<CoordinateKind, String> {
    s.parse()
}

#[derive(Serialize)]
struct Output<P> {
    kind: CoordinateKind,
    vertices: usize,
    faces: usize,
    polygons: usize,
    points: Vec<P>,
}

#[derive(Serialize)]
struct VertexRow<'a> {
    w: &'a [f64],
}

#[derive(Serialize)]
struct GreenRow<'a> {
    phi: &'a [f64],
    psi: &'a [f64],
}

/// Runs the command.
pub fn run(args: &WeightsArgs) -> anyhow::Result<()> {
    let harmonic = HarmonicSettings {
        resolution: args.resolution,
        ..Default::default()
    };
    harmonic
        .check()
        .map_err(|why| InputError(format!("--resolution: {why}")))?;
    let cage = read_cage_obj(&args.cage)?;
    let points = read_points(&args.points)?;
    let settings = BindSettings { harmonic };
    let control = BindControl::default();
    let weights = with_progress("binding", &control, || {
        bind(args.coords, &cage, &points, &settings, &control)
    })
    .map_err(|e| match e {
        CoordError::OutsideCage { .. }
        | CoordError::TooFarForMeanValue { .. }
        | CoordError::NonFinitePoint { .. } => {
            anyhow::Error::new(InputError(format!("{}: {e}", args.points.display())))
        }
        other => anyhow::Error::new(other),
    })?;
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let (vertices, faces, polygons) = (
        cage.vertex_count(),
        cage.triangles().len(),
        cage.polygons().len(),
    );
    match &weights {
        CageWeights::Vertex { kind, weights } => serde_json::to_writer(
            &mut out,
            &Output {
                kind: *kind,
                vertices,
                faces,
                polygons,
                points: (0..weights.point_count())
                    .map(|i| VertexRow { w: weights.row(i) })
                    .collect(),
            },
        ),
        CageWeights::Green(g) => serde_json::to_writer(
            &mut out,
            &Output {
                kind: CoordinateKind::Green,
                vertices,
                faces,
                polygons,
                points: (0..weights.point_count())
                    .map(|i| GreenRow {
                        phi: g.phi_row(i),
                        psi: g.psi_row(i),
                    })
                    .collect(),
            },
        ),
    }
    .context("cannot write the JSON to standard output")?;
    writeln!(out).context("cannot write the JSON to standard output")?;
    out.flush()
        .context("cannot write the JSON to standard output")?;
    Ok(())
}
