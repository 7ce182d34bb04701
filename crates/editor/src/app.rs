//! [`EditorApp`]: the state, the UI's transient state and the command queue, run once per
//! frame by eframe — take finished jobs, draw the UI (which sends commands), apply the
//! commands.

use std::sync::Arc;

use crate::commands::{Command, CommandSender, apply, apply_all};
use crate::state::{Document, EditorState, Waker};
use crate::ui::{UiState, frame_ui};

/// The editor.
pub struct EditorApp {
    /// Document, selection, view, undo, binding, jobs.
    pub state: EditorState,
    /// Input in progress and text being typed.
    pub ui: UiState,
    /// Commands sent this frame, applied at its end.
    pub commands: CommandSender,
}

impl EditorApp {
    /// An editor on `doc`; `repaint` wakes the UI when background work finishes; `gpu`: whether
    /// the 3D view can draw.
    pub fn new(doc: Document, repaint: Option<egui::Context>, gpu: bool) -> Self {
        let waker: Option<Waker> = repaint.map(|ctx| {
            let waker: Waker = Arc::new(move || ctx.request_repaint());
            waker
        });
        Self {
            state: EditorState::new(doc, waker),
            ui: UiState::new(gpu),
            commands: CommandSender::default(),
        }
    }

    /// Applies `command` now (tests and scripts; the UI sends instead).
    pub fn run(&mut self, command: Command) {
        let effects = apply(&mut self.state, command);
        self.ui.effects.extend(effects);
        self.state.poll_jobs(false);
    }

    /// Blocks until every background job (bind, load, baseline) has ended and takes the
    /// results (tests and headless use).
    pub fn wait_for_jobs(&mut self) {
        self.state.poll_jobs(true);
    }
}

impl eframe::App for EditorApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.state.poll_jobs(false);
        if self.state.advance_playback() {
            ctx.request_repaint();
        }
        let busy = self.state.bind_job.is_some()
            || self.state.load_job.is_some()
            || self.state.autorig_job.is_some()
            || self.state.map.baseline_progress().is_some()
            || self.ui.tool.is_some()
            || self.ui.loop_cut.is_some();
        if busy {
            ctx.request_repaint_after(std::time::Duration::from_millis(30));
        }
        // The window's close button is a command like File ▸ Quit: `apply` confirms it at
        // once for a saved document and asks first otherwise (the close waits for the answer).
        if ctx.input(|i| i.viewport().close_requested()) && !self.state.close_confirmed {
            if self.state.doc.dirty {
                ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
            }
            self.commands.send(Command::RequestClose);
        }
        frame_ui(&self.state, &mut self.ui, ui, &mut self.commands);
        let commands = self.commands.take();
        let closing = commands
            .iter()
            .any(|c| matches!(c, Command::AnswerUnsaved(_) | Command::RequestClose));
        let effects = apply_all(&mut self.state, commands);
        self.ui.effects.extend(effects);
        self.state.poll_jobs(false);
        if closing && self.state.close_confirmed {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        ctx.send_viewport_cmd(egui::ViewportCommand::Title(self.state.doc.title()));
    }
}
