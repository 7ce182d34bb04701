//! Choosing files without ever losing the action: the native dialog (rfd) runs on a worker
//! thread, so the editor keeps drawing while it is open; where no native dialog can be shown
//! (no XDG portal and no zenity: rfd then returns at once with nothing), or when asked for
//! (`STARCAGES_FILE_DIALOG=app`), an in-app dialog takes its place.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

/// What a file is chosen for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FilePurpose {
    /// File ▸ Open: a scene or a mesh.
    Open,
    /// File ▸ New from mesh: a mesh.
    NewFromMesh,
    /// File ▸ Save as (or Save of a scene without a file).
    SaveScene,
    /// Save from the unsaved-changes prompt, then carry on with what it asked for.
    SaveBeforeContinuing,
    /// File ▸ Export deformed mesh.
    ExportMesh,
    /// File ▸ Export cages.
    ExportCages,
    /// File ▸ Import cages.
    ImportCages,
    /// File ▸ Import internal cages.
    ImportInternalCages,
    /// File ▸ Import cage animation: a point cache.
    ImportCageAnimation,
}

impl FilePurpose {
    /// The dialog's title and confirm button.
    pub fn title(self) -> &'static str {
        match self {
            Self::Open => "Open",
            Self::NewFromMesh => "New from mesh",
            Self::SaveScene | Self::SaveBeforeContinuing => "Save scene",
            Self::ExportMesh => "Export deformed mesh",
            Self::ExportCages => "Export cages",
            Self::ImportCages => "Import cages",
            Self::ImportInternalCages => "Import internal cages",
            Self::ImportCageAnimation => "Import cage animation",
        }
    }

    /// Whether it names a file to write (else one to read).
    pub fn is_save(self) -> bool {
        matches!(
            self,
            Self::SaveScene | Self::SaveBeforeContinuing | Self::ExportMesh | Self::ExportCages
        )
    }

    /// The file kinds offered.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Self::Open => &["json", "obj", "gltf", "glb", "fbx", "ply", "stl", "off"],
            Self::NewFromMesh => &starcages_io::MESH_EXTENSIONS,
            Self::SaveScene | Self::SaveBeforeContinuing => &["json"],
            Self::ExportMesh => &["obj", "glb"],
            Self::ExportCages | Self::ImportCages | Self::ImportInternalCages => &["obj"],
            Self::ImportCageAnimation => &["pc2", "mdd"],
        }
    }

    /// The file name a save starts with, from the scene file's name (`scene_file`) or else the
    /// mesh file's (`mesh_file`): `armadillo.json`, `armadillo_deformed.obj`,
    /// `armadillo_cages.obj`; generic names for a scene with neither (a demo).
    pub fn suggested_name(self, scene_file: Option<&Path>, mesh_file: Option<&Path>) -> String {
        let stem_of = |path: &Path| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .filter(|s| !s.is_empty())
        };
        let scene_stem = scene_file.and_then(stem_of);
        let stem = scene_stem.clone().or_else(|| mesh_file.and_then(stem_of));
        match self {
            Self::SaveScene | Self::SaveBeforeContinuing => {
                format!("{}.json", stem.as_deref().unwrap_or("scene"))
            }
            Self::ExportMesh => stem.map_or("deformed.obj".into(), |s| format!("{s}_deformed.obj")),
            Self::ExportCages => stem.map_or("cages.obj".into(), |s| format!("{s}_cages.obj")),
            Self::Open
            | Self::NewFromMesh
            | Self::ImportCages
            | Self::ImportInternalCages
            | Self::ImportCageAnimation => String::new(),
        }
    }

    /// [`FilePurpose::suggested_name`] for the document `state` holds.
    pub fn suggested_name_for(self, state: &crate::state::EditorState) -> String {
        let mesh_file = match &state.doc.scene.mesh_source {
            starcages_core::scene::MeshSource::File(path) => Some(path.as_path()),
            starcages_core::scene::MeshSource::Embedded => None,
        };
        self.suggested_name(state.doc.path.as_deref(), mesh_file)
    }

    fn native(self, name: &str) -> Option<PathBuf> {
        let dialog = rfd::FileDialog::new()
            .set_title(self.title())
            .add_filter(self.title(), self.extensions());
        if self.is_save() {
            dialog.set_file_name(name).save_file()
        } else {
            dialog.pick_file()
        }
    }
}

/// A native dialog that answered faster than this was never shown (no person closes one so
/// fast): the in-app dialog is used instead, for the rest of the session.
const NOT_SHOWN: Duration = Duration::from_millis(150);

/// One entry of the in-app dialog's folder listing.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Entry {
    name: String,
    is_folder: bool,
}

/// The in-app file dialog: a folder, its sub-folders and matching files, and a file name.
#[derive(Debug)]
pub struct InAppDialog {
    /// What the file is for.
    pub purpose: FilePurpose,
    /// The folder shown.
    pub folder: PathBuf,
    /// The file name typed or picked.
    pub name: String,
    /// Why the last confirm did nothing (a missing file, a folder that cannot be read).
    pub problem: Option<String>,
    entries: Vec<Entry>,
}

impl InAppDialog {
    /// The dialog for `purpose` showing `folder`, the file name field holding `name`.
    pub fn new(purpose: FilePurpose, folder: PathBuf, name: String) -> Self {
        let mut dialog = Self {
            purpose,
            folder,
            name,
            problem: None,
            entries: Vec::new(),
        };
        dialog.list();
        dialog
    }

    fn list(&mut self) {
        self.entries.clear();
        let extensions = self.purpose.extensions();
        match std::fs::read_dir(&self.folder) {
            Ok(read) => {
                for entry in read.flatten() {
                    let name = entry.file_name().to_string_lossy().into_owned();
                    if name.starts_with('.') {
                        continue;
                    }
                    let is_folder = entry.path().is_dir();
                    let matches = Path::new(&name)
                        .extension()
                        .and_then(|e| e.to_str())
                        .is_some_and(|e| extensions.contains(&e.to_ascii_lowercase().as_str()));
                    if is_folder || matches {
                        self.entries.push(Entry { name, is_folder });
                    }
                }
                self.entries
                    .sort_by(|a, b| (!a.is_folder, &a.name).cmp(&(!b.is_folder, &b.name)));
            }
            Err(e) => self.problem = Some(format!("{}: {e}", self.folder.display())),
        }
    }

    /// Shows `folder` (its listing read again).
    pub fn enter(&mut self, folder: PathBuf) {
        self.folder = folder;
        self.problem = None;
        self.list();
    }

    /// The path to confirm, or why there is none.
    fn chosen(&self) -> Result<PathBuf, String> {
        let name = self.name.trim();
        if name.is_empty() {
            return Err("type or pick a file name".into());
        }
        let path = self.folder.join(name);
        if self.purpose.is_save() {
            if !path.parent().is_some_and(Path::is_dir) {
                return Err(format!("the folder of {} does not exist", path.display()));
            }
        } else if !path.is_file() {
            return Err(format!("{} is not a file", path.display()));
        }
        Ok(path)
    }

    /// Draws the dialog; the path when confirmed, `Some(None)` when cancelled.
    pub fn show(&mut self, ctx: &egui::Context) -> Option<Option<PathBuf>> {
        let mut outcome = None;
        let title = self.purpose.title();
        egui::Modal::new(egui::Id::unique("in-app-file-dialog")).show(ctx, |ui| {
            ui.heading(title);
            ui.horizontal(|ui| {
                if ui
                    .button("Up one folder")
                    .on_hover_text("Show the folder above")
                    .clicked()
                    && let Some(parent) = self.folder.parent().map(Path::to_path_buf)
                {
                    self.enter(parent);
                }
                let mut text = self.folder.display().to_string();
                let edit = ui.add(
                    egui::TextEdit::singleline(&mut text)
                        .desired_width(420.0)
                        .hint_text("folder"),
                );
                if edit.changed() {
                    self.folder = PathBuf::from(&text);
                }
                if edit.lost_focus() {
                    let folder = self.folder.clone();
                    self.enter(folder);
                }
            });
            egui::ScrollArea::vertical()
                .max_height(280.0)
                .show(ui, |ui| {
                    let mut enter = None;
                    for entry in self.entries.clone() {
                        let label = if entry.is_folder {
                            format!("{}/", entry.name)
                        } else {
                            entry.name.clone()
                        };
                        let selected = !entry.is_folder && entry.name == self.name;
                        let response = ui.selectable_label(selected, label);
                        if response.clicked() {
                            if entry.is_folder {
                                enter = Some(self.folder.join(&entry.name));
                            } else {
                                self.name = entry.name.clone();
                            }
                        }
                        if response.double_clicked() && !entry.is_folder {
                            match self.chosen() {
                                Ok(path) => outcome = Some(Some(path)),
                                Err(problem) => self.problem = Some(problem),
                            }
                        }
                    }
                    if self.entries.is_empty() {
                        ui.weak(format!(
                            "no folders or {} files here",
                            self.purpose.extensions().join(", ")
                        ));
                    }
                    if let Some(folder) = enter {
                        self.enter(folder);
                    }
                });
            ui.horizontal(|ui| {
                ui.label("File name");
                ui.add(egui::TextEdit::singleline(&mut self.name).desired_width(360.0));
            });
            if let Some(problem) = &self.problem {
                ui.colored_label(ui.visuals().error_fg_color, problem);
            }
            ui.horizontal(|ui| {
                let confirm = if self.purpose.is_save() {
                    "Save"
                } else {
                    "Open"
                };
                if ui
                    .button(confirm)
                    .on_hover_text(format!("{confirm} the file named above"))
                    .clicked()
                {
                    match self.chosen() {
                        Ok(path) => outcome = Some(Some(path)),
                        Err(problem) => self.problem = Some(problem),
                    }
                }
                if ui.button("Cancel").clicked() {
                    outcome = Some(None);
                }
            });
        });
        outcome
    }
}

/// The file dialogs of the session: a native one running on a worker, or the in-app one.
#[derive(Debug, Default)]
pub struct FileDialogs {
    /// Use the in-app dialog (no native dialog could be shown, or asked for).
    pub in_app_only: bool,
    /// The in-app dialog, while open.
    pub in_app: Option<InAppDialog>,
    native: Option<(FilePurpose, Receiver<Option<PathBuf>>, Instant)>,
    /// The folder the last chosen file was in (where the in-app dialog starts).
    last_folder: Option<PathBuf>,
    /// The file name the open request proposes.
    name: String,
}

impl FileDialogs {
    /// Dialogs as the environment says: `STARCAGES_FILE_DIALOG=app` asks for the in-app one.
    pub fn from_env() -> Self {
        Self {
            in_app_only: std::env::var("STARCAGES_FILE_DIALOG").is_ok_and(|v| v == "app"),
            ..Self::default()
        }
    }

    /// Whether a dialog is open (a second request is ignored meanwhile).
    pub fn is_open(&self) -> bool {
        self.in_app.is_some() || self.native.is_some()
    }

    /// Asks for a file for `purpose`, a save proposing `name`: a native dialog on a worker, or
    /// the in-app one.
    pub fn request(&mut self, purpose: FilePurpose, name: String, wake: Option<egui::Context>) {
        if self.is_open() {
            return;
        }
        self.name = name.clone();
        if self.in_app_only {
            self.open_in_app(purpose);
            return;
        }
        let (sender, receiver) = channel();
        std::thread::spawn(move || {
            sender.send(purpose.native(&name)).ok();
            if let Some(ctx) = wake {
                ctx.request_repaint();
            }
        });
        self.native = Some((purpose, receiver, Instant::now()));
    }

    fn open_in_app(&mut self, purpose: FilePurpose) {
        let folder = self
            .last_folder
            .clone()
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_else(|| PathBuf::from("."));
        self.in_app = Some(InAppDialog::new(purpose, folder, self.name.clone()));
    }

    /// Takes what the dialogs answered this frame (drawing the in-app one): the purpose and
    /// the chosen path. Cancelling gives nothing.
    pub fn poll(&mut self, ctx: &egui::Context) -> Option<(FilePurpose, PathBuf)> {
        if let Some((purpose, receiver, started)) = &self.native {
            let purpose = *purpose;
            match receiver.try_recv() {
                Ok(Some(path)) => {
                    self.native = None;
                    return Some(self.chose(purpose, path));
                }
                Ok(None) | Err(TryRecvError::Disconnected) => {
                    let never_shown = started.elapsed() < NOT_SHOWN;
                    self.native = None;
                    if never_shown {
                        // No native dialog here: use ours from now on.
                        self.in_app_only = true;
                        self.open_in_app(purpose);
                    }
                }
                Err(TryRecvError::Empty) => ctx.request_repaint_after(Duration::from_millis(100)),
            }
        }
        let dialog = self.in_app.as_mut()?;
        let purpose = dialog.purpose;
        let outcome = dialog.show(ctx)?;
        self.in_app = None;
        outcome.map(|path| self.chose(purpose, path))
    }

    fn chose(&mut self, purpose: FilePurpose, path: PathBuf) -> (FilePurpose, PathBuf) {
        self.last_folder = path.parent().map(Path::to_path_buf);
        (purpose, path)
    }

    /// What the status bar says while a native dialog is open.
    pub fn waiting_for(&self) -> Option<&'static str> {
        self.native.as_ref().map(|(purpose, _, _)| purpose.title())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_in_app_dialog_lists_folders_and_matching_files_and_checks_the_choice() {
        let scratch = tempfile::tempdir().unwrap();
        let dir = scratch.path().to_path_buf();
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("a.json"), "{}").unwrap();
        std::fs::write(dir.join("b.txt"), "").unwrap();
        std::fs::write(dir.join(".hidden.json"), "").unwrap();
        let mut open = InAppDialog::new(FilePurpose::Open, dir.clone(), String::new());
        let names: Vec<&str> = open.entries.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(names, ["sub", "a.json"]);
        assert!(open.chosen().is_err(), "nothing typed");
        open.name = "missing.json".into();
        assert!(open.chosen().unwrap_err().contains("not a file"));
        open.name = "a.json".into();
        assert_eq!(open.chosen().unwrap(), dir.join("a.json"));
        let name = FilePurpose::SaveScene.suggested_name(None, None);
        let mut save = InAppDialog::new(FilePurpose::SaveScene, dir.join("nowhere"), name);
        assert_eq!(save.name, "scene.json");
        assert!(save.chosen().unwrap_err().contains("does not exist"));
        save.enter(dir.clone());
        assert_eq!(save.chosen().unwrap(), dir.join("scene.json"));
    }

    #[test]
    fn a_native_dialog_that_answers_at_once_was_never_shown_and_the_in_app_one_opens() {
        let (sender, receiver) = channel();
        sender.send(None).unwrap();
        let mut dialogs = FileDialogs {
            native: Some((FilePurpose::ExportMesh, receiver, Instant::now())),
            name: "deformed.obj".into(),
            ..FileDialogs::default()
        };
        let ctx = egui::Context::default();
        let mut output = ctx.run_ui(egui::RawInput::default(), |ui| {
            assert_eq!(dialogs.poll(ui.ctx()), None);
        });
        output.textures_delta.clear();
        assert!(
            dialogs.in_app_only,
            "the session keeps to the in-app dialog"
        );
        let open = dialogs
            .in_app
            .as_ref()
            .expect("the in-app dialog took over");
        assert_eq!(open.purpose, FilePurpose::ExportMesh);
        assert_eq!(open.name, "deformed.obj");
        // A native dialog closed after a while was shown and cancelled: nothing happens.
        let (sender, receiver) = channel();
        sender.send(None).unwrap();
        let mut dialogs = FileDialogs {
            native: Some((
                FilePurpose::Open,
                receiver,
                Instant::now() - Duration::from_secs(5),
            )),
            ..FileDialogs::default()
        };
        let mut output = ctx.run_ui(egui::RawInput::default(), |ui| {
            assert_eq!(dialogs.poll(ui.ctx()), None);
        });
        output.textures_delta.clear();
        assert!(!dialogs.in_app_only && dialogs.in_app.is_none());
    }

    #[test]
    fn saves_propose_the_scene_s_or_else_the_mesh_s_name() {
        let mesh = Path::new("/meshes/armadillo.obj");
        let scene = Path::new("/rigs/walk.json");
        let name = |purpose: FilePurpose, scene: Option<&Path>, mesh: Option<&Path>| {
            purpose.suggested_name(scene, mesh)
        };
        assert_eq!(
            name(FilePurpose::SaveScene, None, Some(mesh)),
            "armadillo.json"
        );
        assert_eq!(
            name(FilePurpose::SaveScene, Some(scene), Some(mesh)),
            "walk.json"
        );
        assert_eq!(
            name(FilePurpose::SaveBeforeContinuing, None, None),
            "scene.json"
        );
        assert_eq!(
            name(FilePurpose::ExportMesh, None, Some(mesh)),
            "armadillo_deformed.obj"
        );
        assert_eq!(
            name(FilePurpose::ExportCages, Some(scene), None),
            "walk_cages.obj"
        );
        assert_eq!(name(FilePurpose::ExportMesh, None, None), "deformed.obj");
        assert_eq!(name(FilePurpose::Open, Some(scene), Some(mesh)), "");
    }
}
