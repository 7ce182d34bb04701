//! The window's panels: menu bar, outliner, inspector, view options with legend, stats, poses,
//! status bar with bind progress, and the unsaved-changes prompt; plus the eframe entry point.

use egui::{Panel, RichText};
use starcages_core::coords::CoordinateKind;
use starcages_core::scene::{JoinPolicy, Smoothing};
use starcages_viewport::View;

use starcages_core::scene::AutocageOptions;

use crate::app::{EditorApp, InfluenceChoice, Pending};
use crate::interaction;

const KINDS: [CoordinateKind; 3] = [
    CoordinateKind::MeanValue,
    CoordinateKind::Harmonic,
    CoordinateKind::Green,
];

impl eframe::App for EditorApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let now = std::time::Instant::now();
        if let Some(last) = self.last_frame.replace(now) {
            self.stats.frame_ms = (now - last).as_secs_f64() * 1e3;
        }
        let ctx = ui.ctx().clone();
        self.poll_load(false);
        self.poll_bind();
        if self.job.is_some() || self.load.is_some() || self.tool.is_some() {
            ctx.request_repaint_after(std::time::Duration::from_millis(30));
        }
        dropped_files(self, &ctx);
        close_request(self, &ctx);
        ctx.send_viewport_cmd(egui::ViewportCommand::Title(self.doc.title()));
        interaction::shortcuts(self, &ctx);
        Panel::top("menu").show(ui, |ui| menu_bar(self, ui));
        Panel::bottom("status").show(ui, |ui| status_bar(self, ui));
        Panel::left("outliner").default_size(220.0).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| outliner(self, ui));
        });
        Panel::right("inspector")
            .default_size(280.0)
            .show(ui, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    inspector(self, ui);
                    view_options(self, ui);
                    stats(self, ui);
                    poses(self, ui);
                });
            });
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| interaction::viewport_ui(self, ui));
        unsaved_prompt(self, &ctx);
        new_mesh_dialog(self, &ctx);
    }
}

fn menu_bar(app: &mut EditorApp, ui: &mut egui::Ui) {
    egui::MenuBar::new().ui(ui, |ui| {
        ui.menu_button("File", |ui| {
            if ui.button("New from mesh...").clicked()
                && let Some(path) = rfd::FileDialog::new()
                    .add_filter("mesh", &["obj", "gltf", "glb"])
                    .pick_file()
            {
                app.new_mesh_dialog = Some((path, AutocageOptions::default()));
            }
            if ui.button("Open...  Ctrl+O").clicked() {
                open_dialog(app);
            }
            ui.menu_button("Open recent", |ui| {
                if app.recent.is_empty() {
                    ui.label("nothing yet");
                }
                for path in app.recent.clone() {
                    if ui.button(path.display().to_string()).clicked() {
                        request_open(app, path);
                    }
                }
            });
            ui.separator();
            if ui.button("Save  Ctrl+S").clicked() {
                save(app);
            }
            if ui.button("Save As...  Ctrl+Shift+S").clicked() {
                save_as_dialog(app);
            }
            ui.separator();
            if ui.button("Export deformed mesh...").clicked()
                && let Some(path) = rfd::FileDialog::new()
                    .add_filter("mesh", &["obj", "glb"])
                    .set_file_name("deformed.obj")
                    .save_file()
            {
                app.export_mesh(&path);
            }
            if ui.button("Export cages...").clicked()
                && let Some(path) = rfd::FileDialog::new()
                    .add_filter("OBJ", &["obj"])
                    .set_file_name("cages.obj")
                    .save_file()
            {
                app.export_cages(&path);
            }
        });
        ui.menu_button("Edit", |ui| {
            let undo = app.undo.undo_label().map(str::to_owned);
            if ui
                .add_enabled(
                    undo.is_some(),
                    egui::Button::new(format!("Undo {}  Ctrl+Z", undo.unwrap_or_default())),
                )
                .clicked()
            {
                app.undo();
            }
            let redo = app.undo.redo_label().map(str::to_owned);
            if ui
                .add_enabled(
                    redo.is_some(),
                    egui::Button::new(format!("Redo {}  Ctrl+Shift+Z", redo.unwrap_or_default())),
                )
                .clicked()
            {
                app.redo();
            }
            ui.separator();
            ui.checkbox(&mut app.view.mirror_x, "X mirror editing");
        });
        ui.menu_button("View", |ui| {
            if ui.button("Frame all  Home").clicked() {
                app.frame(false);
            }
            if ui.button("Frame selection  F").clicked() {
                app.frame(true);
            }
            for (name, view) in [
                ("Front  1", View::Front),
                ("Side  3", View::Side),
                ("Top  7", View::Top),
            ] {
                if ui.button(name).clicked() {
                    app.view.camera.set_view(view);
                }
            }
        });
    });
}

/// Asks for a file to open (scene or mesh).
pub fn open_dialog(app: &mut EditorApp) {
    if let Some(path) = rfd::FileDialog::new()
        .add_filter("scene or mesh", &["json", "obj", "gltf", "glb"])
        .pick_file()
    {
        request_open(app, path);
    }
}

/// Opens `path`, asking first when there are unsaved changes.
pub fn request_open(app: &mut EditorApp, path: std::path::PathBuf) {
    if app.doc.dirty {
        app.pending = Some(Pending::Open(path));
    } else {
        app.open(&path);
    }
}

/// Saves to the document's file, or asks for one.
pub fn save(app: &mut EditorApp) {
    match app.doc.path.clone() {
        Some(path) => {
            app.save_as(&path);
        }
        None => save_as_dialog(app),
    }
}

/// Asks where to save.
pub fn save_as_dialog(app: &mut EditorApp) {
    if let Some(path) = rfd::FileDialog::new()
        .add_filter("StarCages scene", &["json"])
        .set_file_name("scene.json")
        .save_file()
    {
        app.save_as(&path);
    }
}

fn dropped_files(app: &mut EditorApp, ctx: &egui::Context) {
    let dropped = ctx.input(|i| i.raw.dropped_files.clone());
    if let Some(path) = dropped
        .iter()
        .map(|f| f.path().to_path_buf())
        .find(|p| !p.as_os_str().is_empty())
    {
        request_open(app, path);
    }
}

fn close_request(app: &mut EditorApp, ctx: &egui::Context) {
    if ctx.input(|i| i.viewport().close_requested()) && app.doc.dirty && !app.allow_close {
        ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
        app.pending = Some(Pending::Close);
    }
}

fn unsaved_prompt(app: &mut EditorApp, ctx: &egui::Context) {
    let Some(pending) = app.pending.clone() else {
        return;
    };
    let mut answer = None;
    egui::Modal::new(egui::Id::unique("unsaved-changes")).show(ctx, |ui| {
        ui.heading("Unsaved changes");
        ui.label(format!(
            "{} has changes that are not saved.",
            app.doc.name()
        ));
        ui.horizontal(|ui| {
            if ui.button("Save").clicked() {
                answer = Some(0);
            }
            if ui.button("Don't save").clicked() {
                answer = Some(1);
            }
            if ui.button("Cancel").clicked() {
                answer = Some(2);
            }
        });
    });
    let Some(answer) = answer else {
        return;
    };
    app.pending = None;
    if answer == 2 {
        return;
    }
    if answer == 0 {
        save(app);
        if app.doc.dirty {
            return; // not saved (cancelled or failed): keep the work
        }
    }
    match pending {
        Pending::Open(path) => app.open(&path),
        Pending::NewFromMesh(path, options) => app.new_from_mesh(&path, &options),
        Pending::Close => {
            app.allow_close = true;
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }
}

/// File ▸ New from mesh: grid size, padding and coordinates of the automatic cages.
fn new_mesh_dialog(app: &mut EditorApp, ctx: &egui::Context) {
    let Some((path, mut options)) = app.new_mesh_dialog.clone() else {
        return;
    };
    let mut answer = None;
    egui::Modal::new(egui::Id::unique("new-from-mesh")).show(ctx, |ui| {
        ui.heading("New from mesh");
        ui.label(path.display().to_string());
        ui.horizontal(|ui| {
            ui.label("Grid cells");
            for n in &mut options.grid {
                ui.add(egui::DragValue::new(n).range(1..=16));
            }
        });
        ui.add(egui::Slider::new(&mut options.padding, 0.0..=0.5).text("padding"));
        egui::ComboBox::from_label("Coordinates")
            .selected_text(kind_name(options.kind))
            .show_ui(ui, |ui| {
                for k in KINDS {
                    ui.selectable_value(&mut options.kind, k, kind_name(k));
                }
            });
        ui.horizontal(|ui| {
            if ui.button("Create").clicked() {
                answer = Some(true);
            }
            if ui.button("Cancel").clicked() {
                answer = Some(false);
            }
        });
    });
    match answer {
        Some(true) => {
            app.new_mesh_dialog = None;
            if app.doc.dirty {
                app.pending = Some(Pending::NewFromMesh(path, options));
            } else {
                app.new_from_mesh(&path, &options);
            }
        }
        Some(false) => app.new_mesh_dialog = None,
        None => app.new_mesh_dialog = Some((path, options)),
    }
}

fn outliner(app: &mut EditorApp, ui: &mut egui::Ui) {
    ui.heading("Outliner");
    ui.checkbox(&mut app.view.layers.mesh, "Mesh");
    let leaves = app.doc.scene.cages.leaves.len();
    let names: Vec<(usize, String, CoordinateKind)> = app
        .doc
        .scene
        .cages
        .leaves
        .iter()
        .map(|c| (c.name.clone(), c.kind))
        .chain(
            app.doc
                .scene
                .cages
                .internals
                .iter()
                .map(|c| (c.name.clone(), c.kind)),
        )
        .enumerate()
        .map(|(i, (n, k))| (i, n, k))
        .collect();
    for (title, range) in [
        ("Leaf cages", 0..leaves),
        ("Internal cages", leaves..names.len()),
    ] {
        if range.is_empty() {
            continue;
        }
        egui::CollapsingHeader::new(title)
            .default_open(true)
            .show(ui, |ui| {
                for (i, name, kind) in &names[range] {
                    ui.horizontal(|ui| {
                        let mut visible = !app.view.style.hidden.contains(i);
                        if ui
                            .checkbox(&mut visible, "")
                            .on_hover_text("visible")
                            .changed()
                        {
                            if visible {
                                app.view.style.hidden.remove(i);
                            } else {
                                app.view.style.hidden.insert(*i);
                            }
                        }
                        let selected = app.view.selected_cage == Some(*i);
                        let label = format!("{name} ({})", kind.short_name());
                        if ui.selectable_label(selected, label).clicked() {
                            select_cage(app, *i);
                        }
                    });
                }
            });
    }
}

/// Makes cage `i` the inspected cage and selects its vertices.
pub fn select_cage(app: &mut EditorApp, i: usize) {
    app.view.selected_cage = Some(i);
    let set = &app.doc.scene.cages;
    let faces = if i < set.leaves.len() {
        &set.leaves[i].faces
    } else {
        &set.internals[i - set.leaves.len()].faces
    };
    app.view.style.selected = faces.iter().flatten().copied().collect();
    let levels = starcages_viewport::layers::cage_levels(set);
    app.view.style.focus_level = levels.get(i).copied();
}

fn inspector(app: &mut EditorApp, ui: &mut egui::Ui) {
    ui.heading("Cage");
    if !app.view.style.selected.is_empty() {
        ui.menu_button("Add internal cage around selection", |ui| {
            for k in KINDS {
                if ui.button(kind_name(k)).clicked() {
                    app.add_internal_cage_around_selection(k);
                }
            }
        });
    }
    let Some(cage) = app.view.selected_cage else {
        ui.label("Select a cage in the outliner.");
        scene_settings(app, ui);
        return;
    };
    let leaves = app.doc.scene.cages.leaves.len();
    let (name, mut kind) = if cage < leaves {
        let c = &app.doc.scene.cages.leaves[cage];
        (c.name.clone(), c.kind)
    } else {
        let c = &app.doc.scene.cages.internals[cage - leaves];
        (c.name.clone(), c.kind)
    };
    ui.label(RichText::new(&name).strong());
    let before = kind;
    egui::ComboBox::from_label("Coordinates")
        .selected_text(kind_name(kind))
        .show_ui(ui, |ui| {
            for k in KINDS {
                ui.selectable_value(&mut kind, k, kind_name(k));
            }
        });
    if kind != before {
        app.set_cage_kind(cage, kind);
    }
    if cage < leaves {
        let default_h = app.doc.scene.settings.default_h;
        let mut h = app.doc.scene.cages.leaves[cage].h.unwrap_or(default_h);
        let response = ui.add(egui::Slider::new(&mut h, 0.05..=1.0).text("h"));
        slider_edit(app, &response, "change h", move |scene| {
            scene.cages.leaves[cage].h = Some(h);
        });
        let borders = app.doc.scene.cages.leaves[cage].border_h.clone();
        if !borders.is_empty() {
            ui.label("Per-border h:");
        }
        for (neighbour, mut value) in borders {
            let response = ui.add(egui::Slider::new(&mut value, 0.05..=1.0).text(&neighbour));
            slider_edit(app, &response, "change border h", move |scene| {
                scene.cages.leaves[cage]
                    .border_h
                    .insert(neighbour.clone(), value);
            });
        }
        let neighbours = neighbour_names(app, cage);
        if !neighbours.is_empty() {
            ui.menu_button("Override h on a border", |ui| {
                for n in neighbours {
                    if ui.button(&n).clicked() {
                        let h = app.doc.scene.cage_h(cage);
                        app.edit_scene("add border h", |scene| {
                            scene.cages.leaves[cage].border_h.insert(n.clone(), h);
                        });
                    }
                }
            });
        }
    }
    scene_settings(app, ui);
}

/// An undoable slider edit: one undo step per drag, rebinding when the drag ends.
fn slider_edit(
    app: &mut EditorApp,
    response: &egui::Response,
    label: &str,
    change: impl FnOnce(&mut starcages_core::scene::Scene),
) {
    if !response.changed() && !response.drag_stopped() {
        return;
    }
    if response.dragged() {
        // Live value while dragging; the undo step and the bind come at the end.
        if app.drag_before.is_none() {
            app.drag_before = Some(crate::undo::Snapshot::of(&app.doc.scene));
        }
        change(&mut app.doc.scene);
        return;
    }
    match app.drag_before.take() {
        Some(before) => {
            change(&mut app.doc.scene);
            app.undo.push(label, before);
            app.state_replaced();
        }
        None => app.edit_scene(label, change),
    }
}

fn neighbour_names(app: &EditorApp, cage: usize) -> Vec<String> {
    let set = &app.doc.scene.cages;
    set.adjacency()
        .iter()
        .filter_map(|a| {
            (a.first == cage)
                .then_some(a.second)
                .or((a.second == cage).then_some(a.first))
        })
        .map(|n| set.leaves[n].name.clone())
        .filter(|n| !set.leaves[cage].border_h.contains_key(n))
        .collect()
}

fn scene_settings(app: &mut EditorApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Scene settings").show(ui, |ui| {
        let mut settings = app.doc.scene.settings;
        let response =
            ui.add(egui::Slider::new(&mut settings.default_h, 0.05..=1.0).text("default h"));
        slider_edit(app, &response, "change default h", move |scene| {
            scene.settings.default_h = settings.default_h;
        });
        let mut smoothing = settings.smoothing;
        egui::ComboBox::from_label("Smoothing")
            .selected_text(format!("{smoothing:?}"))
            .show_ui(ui, |ui| {
                for s in [Smoothing::Sine, Smoothing::Cubic, Smoothing::Quintic] {
                    ui.selectable_value(&mut smoothing, s, format!("{s:?}"));
                }
            });
        if smoothing != settings.smoothing {
            app.edit_scene("change smoothing", |scene| {
                scene.settings.smoothing = smoothing
            });
        }
        let mut join = settings.join_coordinates;
        egui::ComboBox::from_label("Join cages")
            .selected_text(format!("{join:?}"))
            .show_ui(ui, |ui| {
                for j in [
                    JoinPolicy::Auto,
                    JoinPolicy::Mvc,
                    JoinPolicy::Hc,
                    JoinPolicy::Gc,
                ] {
                    ui.selectable_value(&mut join, j, format!("{j:?}"));
                }
            });
        if join != settings.join_coordinates {
            app.edit_scene("change join policy", |scene| {
                scene.settings.join_coordinates = join
            });
        }
        let mut resolution = settings.harmonic.resolution;
        let response = ui.add(egui::Slider::new(&mut resolution, 16..=128).text("HC grid"));
        slider_edit(app, &response, "change HC grid", move |scene| {
            scene.settings.harmonic.resolution = resolution;
        });
    });
}

fn kind_name(kind: CoordinateKind) -> &'static str {
    match kind {
        CoordinateKind::MeanValue => "Mean Value (MVC)",
        CoordinateKind::Harmonic => "Harmonic (HC)",
        CoordinateKind::Green => "Green (GC)",
    }
}

fn view_options(app: &mut EditorApp, ui: &mut egui::Ui) {
    ui.separator();
    ui.heading("View");
    let choice = &mut app.view.influence;
    let name = |c: InfluenceChoice| match c {
        InfluenceChoice::None => "none".to_owned(),
        InfluenceChoice::SelectedCage => "b of the selected cage".to_owned(),
        InfluenceChoice::AllCages => "b of all cages".to_owned(),
        InfluenceChoice::JoinWeight => "W of the selected vertex".to_owned(),
        InfluenceChoice::Difference(k) => format!("difference to single {}", k.short_name()),
    };
    egui::ComboBox::from_label("Influence map")
        .selected_text(name(*choice))
        .show_ui(ui, |ui| {
            for c in [
                InfluenceChoice::None,
                InfluenceChoice::SelectedCage,
                InfluenceChoice::AllCages,
                InfluenceChoice::JoinWeight,
                InfluenceChoice::Difference(CoordinateKind::MeanValue),
                InfluenceChoice::Difference(CoordinateKind::Green),
            ] {
                ui.selectable_value(choice, c, name(c));
            }
        });
    let layers = &mut app.view.layers;
    ui.checkbox(&mut layers.wireframe, "Wireframe");
    ui.checkbox(&mut layers.flat, "Flat shading");
    ui.checkbox(&mut layers.cages, "Cages");
    ui.checkbox(&mut layers.vertices, "Cage vertices");
    ui.checkbox(&mut app.view.mirror_x, "X mirror editing");
    if let Some(values) = app.map_values() {
        ui.label(RichText::new(&values.title).small());
        ui.label(
            RichText::new(format!("blue {} — red {}", values.range.0, values.range.1)).small(),
        );
    }
}

fn stats(app: &EditorApp, ui: &mut egui::Ui) {
    ui.separator();
    ui.heading("Stats");
    let scene = &app.doc.scene;
    egui::Grid::new("stats").num_columns(2).show(ui, |ui| {
        let mut row = |k: &str, v: String| {
            ui.label(k);
            ui.label(v);
            ui.end_row();
        };
        row("vertices", scene.mesh.welded_positions().len().to_string());
        row("triangles", scene.mesh.welded_triangles().len().to_string());
        row(
            "cages",
            format!(
                "{} leaf, {} internal",
                scene.cages.leaves.len(),
                scene.cages.internals.len()
            ),
        );
        row("cage vertices", scene.cages.vertices.len().to_string());
        if let Some(rig) = &app.rig {
            let b = &rig.binding;
            let bytes =
                b.stats.operator_bytes + b.stats.transpose_bytes + b.join_weights.byte_size();
            row("weights memory", format!("{:.2} MB", bytes as f64 / 1e6));
        }
        if app.show_timings {
            row("last bind", format!("{:.2} s", app.stats.bind_seconds));
            row("deform update", format!("{:.2} ms", app.stats.deform_ms));
            row("frame", format!("{:.1} ms", app.stats.frame_ms));
        }
    });
}

fn poses(app: &mut EditorApp, ui: &mut egui::Ui) {
    ui.separator();
    ui.heading("Poses");
    let names: Vec<String> = app.doc.scene.poses.keys().cloned().collect();
    for name in names {
        ui.horizontal(|ui| {
            if ui
                .button(&name)
                .on_hover_text("switch to this pose")
                .clicked()
            {
                switch_pose(app, Some(&name));
            }
            if ui
                .small_button("delete")
                .on_hover_text("delete this pose")
                .clicked()
            {
                app.checkpoint("delete pose");
                app.doc.scene.poses.remove(&name);
                app.doc.scene.pose_states.remove(&name);
                app.doc.dirty = true;
            }
        });
    }
    ui.horizontal(|ui| {
        ui.text_edit_singleline(&mut app.new_pose_name);
        if ui.button("Store pose").clicked() && !app.new_pose_name.trim().is_empty() {
            let name = app.new_pose_name.trim().to_owned();
            app.checkpoint("store pose");
            let scene = &mut app.doc.scene;
            scene.poses.insert(name.clone(), scene.pose.clone());
            scene.pose_states.insert(name, scene.pose_state.clone());
            app.doc.dirty = true;
            app.new_pose_name.clear();
        }
    });
    if ui.button("Reset to rest").clicked() {
        switch_pose(app, None);
    }
}

/// Switches to a stored pose (or the rest pose for `None`) as an undoable edit.
pub fn switch_pose(app: &mut EditorApp, name: Option<&str>) {
    app.checkpoint("switch pose");
    let scene = &mut app.doc.scene;
    match name {
        Some(n) => {
            if let Some(pose) = scene.poses.get(n) {
                scene.pose = pose.clone();
                scene.pose_state = scene.pose_states.get(n).cloned().unwrap_or_default();
            }
        }
        None => {
            scene.pose = scene.cages.vertices.clone();
            scene.pose_state = Default::default();
        }
    }
    app.state_replaced();
}

fn status_bar(app: &mut EditorApp, ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        if let Some(load) = &app.load {
            ui.spinner();
            ui.label(format!("opening {}", load.path.display()));
            if ui.button("Cancel").clicked() {
                app.load = None;
                app.info("opening cancelled; the current scene is unchanged".into());
                return;
            }
        }
        if let Some(job) = &app.job {
            let fraction = job.progress();
            ui.label(&job.label);
            ui.add(egui::ProgressBar::new(fraction as f32).desired_width(160.0).show_percentage());
            if ui.button("Cancel").clicked() {
                job.cancel();
            }
        }
        if let Some(tool) = &app.tool {
            ui.label(tool.describe());
        } else if let Some(message) = &app.message {
            let colour = if message.error {
                egui::Color32::from_rgb(255, 110, 100)
            } else {
                ui.visuals().text_color()
            };
            ui.label(RichText::new(&message.text).color(colour));
        } else {
            ui.label("Click a cage vertex to select it, drag to move; G/R/S transform; middle mouse orbits.");
        }
    });
}
