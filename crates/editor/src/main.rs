//! `starcages`: the StarCages desktop cage editor. `starcages` opens the built-in demo scene,
//! `starcages SCENE.json` or `starcages MESH.obj` opens a file, `--help` and `--version` answer
//! on the terminal.

use anyhow::Context as _;
use starcages_editor::Document;
use starcages_editor::launch::{self, Launch};
use starcages_editor::state::recent;

fn main() -> anyhow::Result<()> {
    // Ctrl-C or SIGTERM in the terminal: remove a save's temporary file before exiting (the
    // file saved to keeps its old content).
    ctrlc::set_handler(|| {
        starcages_io::remove_unfinished_saves();
        std::process::exit(130);
    })
    .ok();
    let path = match launch::parse(std::env::args_os().skip(1)) {
        Launch::Open(path) => path,
        Launch::Help => {
            println!("{}", launch::usage());
            return Ok(());
        }
        Launch::Version => {
            println!("starcages {}", env!("CARGO_PKG_VERSION"));
            return Ok(());
        }
        Launch::Invalid(message) => {
            eprintln!("error: {message}");
            std::process::exit(2);
        }
    };
    // The window opens at once on the demo; a file named on the command line opens on a worker
    // (a mesh is rigged there), with progress and Cancel in the status bar, as File ▸ Open.
    let doc = Document::demo();
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(doc.title())
            .with_inner_size([1400.0, 900.0])
            .with_drag_and_drop(true),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    eframe::run_native(
        "StarCages",
        options,
        Box::new(move |cc| {
            let mut app = starcages_editor::create(cc, doc);
            let state = &mut app.state;
            state.recent_file = recent::default_file();
            if let Some(file) = &state.recent_file {
                state.recent = recent::load(file);
            }
            if let Some(path) = path {
                state.start_load(path);
            }
            Ok(Box::new(app))
        }),
    )
    .map_err(|e| anyhow::anyhow!("{e}"))
    .context("the editor window could not be opened (is there a display?)")
}
