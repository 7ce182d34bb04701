//! The menu and keyboard actions: one table gives each its label, tooltip and shortcut, and
//! the menus, the key handling and the tooltips all read it, so no label or key is typed twice.

use egui::{Key, KeyboardShortcut, Modifiers};

use crate::state::EditMode;

/// Declares an enum and its `ALL` from one list of variants ([`UiCommand`], [`ToolKey`]), so
/// no action can be left out of the menus, the key handling or Help.
macro_rules! ui_commands {
    (
        $(#[$enum_meta:meta])*
        pub enum $name:ident { $( $(#[$meta:meta])* $variant:ident, )* }
    ) => {
        $(#[$enum_meta])*
        pub enum $name { $( $(#[$meta])* $variant, )* }

        impl $name {
            /// Every action, in menu order (the order they are declared in).
            pub const ALL: [Self; [$(stringify!($variant)),*].len()] = [$(Self::$variant),*];
        }
    };
}

ui_commands! {
/// An action from a menu or a key. The UI layer carries it out (some need a file dialog or
/// the pointer) by sending [`super::Command`]s.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UiCommand {
    /// File ▸ New from mesh…
    NewFromMesh,
    /// File ▸ Open…
    Open,
    /// File ▸ Save
    Save,
    /// File ▸ Save as…
    SaveAs,
    /// File ▸ Export deformed mesh…
    ExportMesh,
    /// File ▸ Export cages…
    ExportCages,
    /// File ▸ Import cages…
    ImportCages,
    /// File ▸ Import internal cages…
    ImportInternalCages,
    /// Edit ▸ Undo
    Undo,
    /// Edit ▸ Redo
    Redo,
    /// Edit ▸ X mirror editing
    ToggleMirrorX,
    /// Select ▸ All
    SelectAll,
    /// Select ▸ None
    SelectNone,
    /// Transform ▸ Grab
    Grab,
    /// Transform ▸ Rotate
    Rotate,
    /// Transform ▸ Scale
    Scale,
    /// View ▸ Frame all
    FrameAll,
    /// View ▸ Frame selection
    FrameSelection,
    /// View ▸ Front
    ViewFront,
    /// View ▸ Side
    ViewSide,
    /// View ▸ Top
    ViewTop,
    /// View ▸ Back
    ViewBack,
    /// View ▸ Left
    ViewLeft,
    /// View ▸ Bottom
    ViewBottom,
    /// View ▸ Perspective / orthographic
    ToggleOrthographic,
    /// View ▸ Item panel (the selection's coordinates)
    ToggleItemPanel,
    /// View ▸ X-ray
    ToggleXray,
    /// View ▸ Outliner (the left panel)
    ToggleOutliner,
    /// View ▸ Properties (the right panel)
    ToggleProperties,
    /// Help ▸ Keyboard shortcuts
    ShowShortcuts,
    /// Edit ▸ Pose / Rig mode
    ToggleMode,
    /// Rig ▸ Extrude face
    Extrude,
    /// Rig ▸ Inset faces
    InsetFaces,
    /// Rig ▸ Loop cut
    LoopCut,
    /// Rig ▸ Add box cage
    AddBox,
    /// Rig ▸ Delete cage
    DeleteCage,
    /// Rig ▸ Merge with neighbour
    MergeCages,
    /// Rig ▸ Mirror across X
    MirrorCage,
    /// Rig ▸ Fit to mesh
    FitCage,
    /// Rig ▸ Subdivide
    SubdivideCages,
    /// Rig ▸ Auto rig
    AutoRig,
    /// Animation ▸ Play / pause
    PlayPause,
    /// Animation ▸ Jump to start
    JumpToStart,
    /// Animation ▸ Jump to end
    JumpToEnd,
    /// Animation ▸ Next frame
    NextFrame,
    /// Animation ▸ Previous frame
    PreviousFrame,
    /// Animation ▸ Next key
    NextKey,
    /// Animation ▸ Previous key
    PreviousKey,
    /// Animation ▸ Insert key
    InsertKey,
    /// Animation ▸ Delete key
    DeleteKey,
    /// Animation ▸ Auto-key
    ToggleAutoKey,
    /// File ▸ Import cage animation…
    ImportCageAnimation,
}
}

const fn key(modifiers: Modifiers, key: Key) -> KeyboardShortcut {
    KeyboardShortcut::new(modifiers, key)
}

const NONE: Modifiers = Modifiers::NONE;
const CMD: Modifiers = Modifiers::COMMAND;
ui_commands! {
/// A key of a modal tool while it runs (G / R / S, Ctrl+R's loop cut, I's inset): the keys
/// read it through [`ToolKey::of_char`] and [`ToolKey::of_key`], and Help lists it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ToolKey {
    /// Lock the move to the world X axis (again: unlock).
    LockX,
    /// Lock to Y.
    LockY,
    /// Lock to Z.
    LockZ,
    /// Type the amount.
    Digit,
    /// Take back the last typed character.
    Backspace,
    /// Make it.
    Confirm,
    /// Drop it.
    Cancel,
}
}

impl ToolKey {
    /// What it does, for Help.
    pub fn label(self) -> &'static str {
        match self {
            Self::LockX => "Lock to X (again: free)",
            Self::LockY => "Lock to Y (again: free)",
            Self::LockZ => "Lock to Z (again: free)",
            Self::Digit => "Type the amount",
            Self::Backspace => "Take back a typed character",
            Self::Confirm => "Confirm",
            Self::Cancel => "Cancel",
        }
    }

    /// Its keys, as Help writes them.
    pub fn keys(self) -> &'static str {
        match self {
            Self::LockX => "X",
            Self::LockY => "Y",
            Self::LockZ => "Z",
            Self::Digit => "0–9, '.', '-' (G / R / S only)",
            Self::Backspace => "Backspace",
            Self::Confirm => "Enter or a click",
            Self::Cancel => "Esc, a right click or Ctrl+Z",
        }
    }

    /// The tools it works in.
    pub fn tools(self) -> &'static str {
        match self {
            Self::LockX | Self::LockY | Self::LockZ => "G / R / S",
            _ => "G / R / S, loop cut, inset",
        }
    }

    /// The tool key a typed character is, if any.
    pub fn of_char(c: char) -> Option<Self> {
        match c {
            'x' | 'X' => Some(Self::LockX),
            'y' | 'Y' => Some(Self::LockY),
            'z' | 'Z' => Some(Self::LockZ),
            '0'..='9' | '.' | '-' => Some(Self::Digit),
            _ => None,
        }
    }

    /// The tool key a pressed key is, if any (typed characters come as text instead).
    pub fn of_key(key: Key, modifiers: Modifiers) -> Option<Self> {
        match key {
            Key::Backspace => Some(Self::Backspace),
            Key::Enter => Some(Self::Confirm),
            Key::Escape => Some(Self::Cancel),
            // Ctrl+Z cancels the tool (the Undo command does that while a gesture runs).
            Key::Z if modifiers.command => Some(Self::Cancel),
            _ => None,
        }
    }
}

const CMD_SHIFT: Modifiers = Modifiers::COMMAND.plus(Modifiers::SHIFT);
const SHIFT: Modifiers = Modifiers::SHIFT;

impl UiCommand {
    /// The label in menus ("…" where a dialog follows).
    pub fn label(self) -> &'static str {
        match self {
            Self::NewFromMesh => "New from mesh…",
            Self::Open => "Open…",
            Self::Save => "Save",
            Self::SaveAs => "Save as…",
            Self::ExportMesh => "Export deformed mesh…",
            Self::ExportCages => "Export cages…",
            Self::ImportCages => "Import cages…",
            Self::ImportInternalCages => "Import internal cages…",
            Self::Undo => "Undo",
            Self::Redo => "Redo",
            Self::ToggleMirrorX => "X mirror editing",
            Self::SelectAll => "Select all",
            Self::SelectNone => "Select none",
            Self::Grab => "Grab",
            Self::Rotate => "Rotate",
            Self::Scale => "Scale",
            Self::FrameAll => "Frame all",
            Self::FrameSelection => "Frame selection",
            Self::ViewFront => "Front",
            Self::ViewSide => "Side",
            Self::ViewTop => "Top",
            Self::ViewBack => "Back",
            Self::ViewLeft => "Left",
            Self::ViewBottom => "Bottom",
            Self::ToggleOrthographic => "Perspective / orthographic",
            Self::ToggleItemPanel => "Item panel",
            Self::ToggleXray => "X-ray",
            Self::ToggleOutliner => "Outliner",
            Self::ToggleProperties => "Properties panel",
            Self::ShowShortcuts => "Keyboard shortcuts",
            Self::ToggleMode => "Pose / Rig mode",
            Self::Extrude => "Extrude face",
            Self::InsetFaces => "Inset faces",
            Self::LoopCut => "Loop cut",
            Self::AddBox => "Add box cage",
            Self::DeleteCage => "Delete cage",
            Self::MergeCages => "Merge with neighbour",
            Self::MirrorCage => "Mirror across X",
            Self::FitCage => "Fit to mesh",
            Self::SubdivideCages => "Subdivide",
            Self::AutoRig => "Auto rig…",
            Self::PlayPause => "Play / pause",
            Self::JumpToStart => "Jump to start",
            Self::JumpToEnd => "Jump to end",
            Self::NextFrame => "Next frame",
            Self::PreviousFrame => "Previous frame",
            Self::NextKey => "Next key",
            Self::PreviousKey => "Previous key",
            Self::InsertKey => "Insert key",
            Self::DeleteKey => "Delete key",
            Self::ToggleAutoKey => "Auto-key",
            Self::ImportCageAnimation => "Import cage animation…",
        }
    }

    /// What it does, in plain words (menu tooltips).
    pub fn tooltip(self) -> &'static str {
        match self {
            Self::NewFromMesh => {
                "Rig a mesh (OBJ, glTF, GLB, FBX, PLY, STL, OFF): the auto rig (chains of cages along its limbs) or a \
                 grid of box cages"
            }
            Self::Open => "Open a scene (.json) or a mesh, which gets automatic cages",
            Self::Save => "Save the scene to its file (atomic: a failed save overwrites nothing)",
            Self::SaveAs => "Save the scene to a new file",
            Self::ExportMesh => "Write the deformed mesh as OBJ or GLB",
            Self::ExportCages => "Write the cages in the current pose as OBJ",
            Self::ImportCages => {
                "Add the cages of an OBJ file (one leaf cage per o/g group) to the rig; corners \
                 at the positions of existing cage vertices are shared"
            }
            Self::ImportInternalCages => {
                "Add the cages of an OBJ file (one per o/g group) as internal cages: each drives \
                 the cage vertices inside it that have no parent yet"
            }
            Self::Undo => "Undo the last edit (a whole drag is one step)",
            Self::Redo => "Redo the last undone edit",
            Self::ToggleMirrorX => "Moving a vertex also moves its mirror image across x = 0",
            Self::SelectAll => {
                "Select everything the select mode picks: every vertex of the drawn cages, or in Rig mode every face or mesh vertex"
            }
            Self::SelectNone => "Clear the selection",
            Self::Grab => {
                "Move the selection with the mouse; X/Y/Z lock an axis, type a distance, Enter confirms, Esc cancels"
            }
            Self::Rotate => {
                "Rotate the selection about its centre; X/Y/Z pick the axis, type degrees"
            }
            Self::Scale => "Scale the selection about its centre; X/Y/Z scale along one axis",
            Self::FrameAll => "Fit the mesh and the cages in the view",
            Self::FrameSelection => "Fit the selected vertices in the view",
            Self::ViewFront => "Look along +Y",
            Self::ViewSide => "Look along -X",
            Self::ViewTop => "Look down -Z",
            Self::ViewBack => "Look along -Y (the opposite of Front)",
            Self::ViewLeft => "Look along +X (the opposite of Side)",
            Self::ViewBottom => "Look up +Z (the opposite of Top)",
            Self::ToggleOrthographic => {
                "Switch between perspective and orthographic projection (parallel lines stay parallel)"
            }
            Self::ToggleItemPanel => {
                "Show or hide the coordinates of the selected vertices (rest and posed), editable"
            }
            Self::ToggleXray => {
                "See the cages through the mesh, drawn translucent (its opacity in the View panel)"
            }
            Self::ToggleOutliner => {
                "Show or hide the left panel (the cages); a narrow window hides it by itself"
            }
            Self::ToggleProperties => {
                "Show or hide the right panel (cage, view, stats, poses); a narrow window hides \
                 it by itself"
            }
            Self::ShowShortcuts => "List every action with its keys",
            Self::ToggleMode => {
                "Pose mode poses the mesh; Rig mode edits the rest cages (the binding), with the \
                 rig operations on keys"
            }
            Self::Extrude => {
                "Rig mode: a new cage on the selected face of a leaf cage, sharing that face; \
                 then move its cap along the face's normal (type a distance, Enter, or Esc to \
                 keep the default depth)"
            }
            Self::InsetFaces => {
                "Rig mode: each selected free face becomes a smaller face inside it, joined to it \
                 by a ring of quads; move the mouse to size it (or type a thickness), then click \
                 or Enter. A cage extruded from the inner face touches no other cage"
            }
            Self::LoopCut => {
                "Rig mode: cut the inspected cage in two across its longest side; slide the cut \
                 with the mouse (or type a fraction), then click or Enter"
            }
            Self::AddBox => {
                "Rig mode: a box cage around the selected mesh or cage vertices, around the \
                 mesh, or in the part of the mesh under the pointer (Shift+A opens the menu)"
            }
            Self::DeleteCage => "Rig mode: delete the inspected leaf cage",
            Self::MergeCages => {
                "Rig mode: merge the inspected cage with the neighbour whose shared face is \
                 selected (or its only neighbour)"
            }
            Self::MirrorCage => "Rig mode: a copy of the inspected cage mirrored across x = 0",
            Self::SubdivideCages => {
                "Rig mode: cut every face of every leaf cage into quads through its edge \
                 midpoints and centre (more vertices to pose; the shape does not change)"
            }
            Self::FitCage => {
                "Rig mode: pull the inspected cage in to the mesh (vertices it shares stay), \
                 keeping a margin of 2 % of the mesh's size"
            }
            Self::AutoRig => {
                "Replace the rig with one that follows the mesh's shape: a chain of cages along \
                 each limb, a few across the body, an internal cage per limb to pose it \
                 (in the background; one undo step)"
            }
            Self::PlayPause => {
                "Play the animation in real time, looping over its range; again to stop"
            }
            Self::JumpToStart => "Go to the first frame of the range",
            Self::JumpToEnd => "Go to the last frame of the range",
            Self::NextFrame => "One frame forward",
            Self::PreviousFrame => "One frame back",
            Self::NextKey => "Go to the next key",
            Self::PreviousKey => "Go to the previous key",
            Self::InsertKey => {
                "Pose mode: key the current pose at the current frame (the key there takes it)"
            }
            Self::DeleteKey => {
                "Pose mode: delete the key selected on the timeline, or the one at the current frame"
            }
            Self::ToggleAutoKey => {
                "Moving a cage vertex at a frame without a key inserts one (a keyed frame's key \
                 always takes the edit)"
            }
            Self::ImportCageAnimation => {
                "Keys from a cage point cache (PC2 or MDD) written by another tool, in the vertex \
                 order and axes of Export cages: one linear key per sample"
            }
        }
    }

    /// Its keyboard shortcuts (the first is shown in menus).
    pub fn shortcuts(self) -> &'static [KeyboardShortcut] {
        match self {
            Self::NewFromMesh
            | Self::ExportMesh
            | Self::ExportCages
            | Self::ImportCages
            | Self::ImportInternalCages
            | Self::ToggleMirrorX => &[],
            Self::Open => &const { [key(CMD, Key::O)] },
            Self::Save => &const { [key(CMD, Key::S)] },
            Self::SaveAs => &const { [key(CMD_SHIFT, Key::S)] },
            Self::Undo => &const { [key(CMD, Key::Z)] },
            Self::Redo => &const { [key(CMD_SHIFT, Key::Z), key(CMD, Key::Y)] },
            Self::SelectAll => &const { [key(NONE, Key::A)] },
            Self::SelectNone => &const { [key(Modifiers::ALT, Key::A)] },
            Self::Grab => &const { [key(NONE, Key::G)] },
            Self::Rotate => &const { [key(NONE, Key::R)] },
            Self::Scale => &const { [key(NONE, Key::S)] },
            Self::FrameAll => &const { [key(NONE, Key::Home)] },
            Self::FrameSelection => &const { [key(NONE, Key::F), key(NONE, Key::Period)] },
            Self::ViewFront => &const { [key(NONE, Key::Num1)] },
            Self::ViewSide => &const { [key(NONE, Key::Num3)] },
            Self::ViewTop => &const { [key(NONE, Key::Num7)] },
            Self::ViewBack => &const { [key(CMD, Key::Num1)] },
            Self::ViewLeft => &const { [key(CMD, Key::Num3)] },
            Self::ViewBottom => &const { [key(CMD, Key::Num7)] },
            Self::ToggleOrthographic => &const { [key(NONE, Key::Num5)] },
            Self::ToggleItemPanel => &const { [key(NONE, Key::N)] },
            Self::ToggleXray => &const { [key(Modifiers::ALT, Key::Z)] },
            Self::ToggleOutliner => &const { [key(NONE, Key::T)] },
            Self::ToggleProperties => &const { [key(SHIFT, Key::T)] },
            Self::ToggleMode => &const { [key(NONE, Key::Tab)] },
            Self::Extrude => &const { [key(NONE, Key::E)] },
            Self::InsetFaces => &const { [key(NONE, Key::I)] },
            Self::LoopCut => &const { [key(CMD, Key::R)] },
            Self::AddBox => &const { [key(Modifiers::SHIFT, Key::A)] },
            Self::DeleteCage => &const { [key(NONE, Key::X), key(NONE, Key::Delete)] },
            Self::MergeCages => &const { [key(NONE, Key::M)] },
            Self::MirrorCage => &const { [key(CMD, Key::M)] },
            Self::FitCage | Self::SubdivideCages | Self::AutoRig => &[],
            Self::ToggleAutoKey | Self::ImportCageAnimation => &[],
            Self::PlayPause => &const { [key(NONE, Key::Space)] },
            Self::JumpToStart => &const { [key(Modifiers::SHIFT, Key::ArrowLeft)] },
            Self::JumpToEnd => &const { [key(Modifiers::SHIFT, Key::ArrowRight)] },
            Self::NextFrame => &const { [key(NONE, Key::ArrowRight)] },
            Self::PreviousFrame => &const { [key(NONE, Key::ArrowLeft)] },
            Self::NextKey => &const { [key(NONE, Key::ArrowUp)] },
            Self::PreviousKey => &const { [key(NONE, Key::ArrowDown)] },
            Self::InsertKey => &const { [key(NONE, Key::I)] },
            Self::DeleteKey => &const { [key(Modifiers::ALT, Key::I), key(NONE, Key::X)] },
            Self::ShowShortcuts => {
                &const {
                    [
                        key(NONE, Key::F1),
                        key(NONE, Key::Questionmark),
                        key(Modifiers::SHIFT, Key::Questionmark),
                    ]
                }
            }
        }
    }

    /// The mode whose keys it owns, for an action whose shortcut means something else in the
    /// other mode (I insets faces in Rig mode and keys the pose in Pose mode, as in Blender's
    /// edit and pose modes); `None`: the same in both.
    pub fn mode(self) -> Option<EditMode> {
        match self {
            Self::Extrude
            | Self::InsetFaces
            | Self::LoopCut
            | Self::AddBox
            | Self::DeleteCage
            | Self::MergeCages
            | Self::MirrorCage
            | Self::FitCage
            | Self::SubdivideCages => Some(EditMode::Rig),
            Self::InsertKey | Self::DeleteKey => Some(EditMode::Pose),
            _ => None,
        }
    }

    /// The action whose shortcut is exactly `key` with `modifiers` (Ctrl and ⌘ count as one)
    /// in `mode`: the one owned by that mode first, else any (which then says it belongs to the
    /// other mode).
    pub fn for_key(key: Key, modifiers: Modifiers, mode: EditMode) -> Option<Self> {
        let matching = |c: &Self| {
            c.shortcuts().iter().any(|s| {
                s.logical_key == key
                    && s.modifiers.command == modifiers.command
                    && s.modifiers.shift == modifiers.shift
                    && s.modifiers.alt == modifiers.alt
            })
        };
        let mut candidates = Self::ALL.into_iter().filter(matching);
        let first = candidates.next()?;
        Some(
            std::iter::once(first)
                .chain(candidates)
                .find(|c| c.mode().is_none_or(|m| m == mode))
                .unwrap_or(first),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_actions_share_a_shortcut_in_a_mode_or_a_label() {
        let mut seen = std::collections::BTreeSet::new();
        for command in UiCommand::ALL {
            assert!(seen.insert(command.label()), "{}", command.label());
            for s in command.shortcuts() {
                for mode in [EditMode::Pose, EditMode::Rig] {
                    let found = UiCommand::for_key(s.logical_key, s.modifiers, mode);
                    if command.mode().is_none_or(|m| m == mode) {
                        assert_eq!(found, Some(command), "{s:?} in {mode:?}");
                    }
                }
            }
        }
        let pose = EditMode::Pose;
        assert_eq!(UiCommand::for_key(Key::S, CMD, pose), Some(UiCommand::Save));
        assert_eq!(
            UiCommand::for_key(Key::S, NONE, pose),
            Some(UiCommand::Scale)
        );
        assert_eq!(
            UiCommand::for_key(Key::A, Modifiers::ALT, pose),
            Some(UiCommand::SelectNone)
        );
        assert_eq!(UiCommand::for_key(Key::Q, NONE, pose), None);
        // I and X: keys in Pose mode, rig operations in Rig mode; E only in Rig mode, which
        // Pose mode then explains.
        assert_eq!(
            UiCommand::for_key(Key::I, NONE, pose),
            Some(UiCommand::InsertKey)
        );
        assert_eq!(
            UiCommand::for_key(Key::I, NONE, EditMode::Rig),
            Some(UiCommand::InsetFaces)
        );
        assert_eq!(
            UiCommand::for_key(Key::X, NONE, pose),
            Some(UiCommand::DeleteKey)
        );
        assert_eq!(
            UiCommand::for_key(Key::E, NONE, pose),
            Some(UiCommand::Extrude)
        );
    }
}
