//! `starcages-cli demo`: write a generated demo scene (mesh embedded) to a folder.

use std::path::PathBuf;

use clap::Args;
use starcages_core::generate::demo::{DEMOS, demo_scene};
use starcages_io::save_scene;

use crate::InputError;

/// Arguments of `demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Demo name (see --list), or `all`.
    #[arg(required_unless_present = "list")]
    name: Option<String>,
    /// List the demos and exit.
    #[arg(long)]
    list: bool,
    /// Folder to write NAME.json into (created if missing).
    #[arg(long, required_unless_present = "list")]
    out: Option<PathBuf>,
    /// Tessellation multiplier (1 = default; the prism has about 200k triangles at 3).
    #[arg(long, default_value_t = 1.0)]
    detail: f64,
}

/// Runs the command.
pub fn run(args: &DemoArgs) -> anyhow::Result<()> {
    if args.list {
        for (name, description) in DEMOS {
            crate::output::line(format_args!("{name:8} {description}"))?;
        }
        return Ok(());
    }
    let (Some(name), Some(out)) = (&args.name, &args.out) else {
        return Err(InputError("give a demo name and --out FOLDER (or --list)".into()).into());
    };
    if !(args.detail > 0.0 && args.detail <= 8.0) {
        return Err(InputError(format!(
            "--detail {} is out of range; use a value in (0, 8]",
            args.detail
        ))
        .into());
    }
    let names: Vec<&str> = if name == "all" {
        DEMOS.iter().map(|(n, _)| *n).collect()
    } else {
        vec![name.as_str()]
    };
    std::fs::create_dir_all(out)
        .map_err(|e| InputError(format!("{}: cannot create folder: {e}", out.display())))?;
    for name in names {
        let scene = demo_scene(name, args.detail).ok_or_else(|| {
            let known: Vec<&str> = DEMOS.iter().map(|(n, _)| *n).collect();
            InputError(format!(
                "unknown demo '{name}'; known demos: {}",
                known.join(", ")
            ))
        })?;
        let path = out.join(format!("{name}.json"));
        save_scene(&scene, &path)?;
        crate::output::line(format_args!("{}", path.display()))?;
    }
    Ok(())
}
