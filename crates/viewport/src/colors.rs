//! The colour code: the paper's (blue MVC, green GC, red HC, pink borders), grey internal
//! cages, selection and hover highlights, the studio mesh colour and the blue–red ramp of
//! influence maps (with its legend).

use starcages_core::coords::CoordinateKind;

/// Linear RGBA in 0..1.
pub type Rgba = [f32; 4];

/// Mesh colour without an influence map: a neutral clay.
pub const MESH: Rgba = [0.74, 0.72, 0.68, 1.0];
/// Mesh vertices a map has no value for (outside the chosen cage).
pub const NO_VALUE: Rgba = [0.55, 0.55, 0.55, 1.0];
/// Internal cages.
pub const INTERNAL: Rgba = [0.62, 0.62, 0.62, 1.0];
/// Borders between leaf cages (faces shared by two cages).
pub const BORDER: Rgba = [1.0, 0.42, 0.75, 1.0];
/// The current pose's cages drawn faintly over the rest cages (Rig mode's ghost).
pub const GHOST: Rgba = [0.47, 0.47, 0.52, 1.0];
/// Cages, cage vertices and mesh vertices with a problem (Rig mode's live validation).
pub const WARNING: Rgba = [1.0, 0.85, 0.1, 1.0];
/// Selected cage vertices.
pub const SELECTED: Rgba = [1.0, 0.6, 0.08, 1.0];
/// The hovered cage vertex.
pub const HOVERED: Rgba = [1.0, 1.0, 0.55, 1.0];
/// Cage vertices not selected.
pub const VERTEX: Rgba = [0.12, 0.12, 0.14, 1.0];
/// Background at the top of the viewport.
pub const BACKGROUND_TOP: Rgba = [0.30, 0.31, 0.34, 1.0];
/// Background at the bottom of the viewport.
pub const BACKGROUND_BOTTOM: Rgba = [0.16, 0.16, 0.18, 1.0];
/// Mesh wireframe overlay.
pub const WIREFRAME: Rgba = [0.1, 0.1, 0.1, 1.0];
/// Ground grid lines.
pub const GRID: Rgba = [0.36, 0.37, 0.40, 1.0];
/// The X axis on the ground grid (Blender's red).
pub const X_AXIS: Rgba = [0.80, 0.27, 0.30, 1.0];
/// The Y axis on the ground grid (Blender's green).
pub const Y_AXIS: Rgba = [0.45, 0.66, 0.22, 1.0];
/// The Z axis (Blender's blue), in the axis gizmo.
pub const Z_AXIS: Rgba = [0.25, 0.48, 0.86, 1.0];

/// The colour of a leaf cage of `kind` (the paper's code).
pub fn kind(kind: CoordinateKind) -> Rgba {
    match kind {
        CoordinateKind::MeanValue => [0.16, 0.42, 1.0, 1.0],
        CoordinateKind::Green => [0.12, 0.75, 0.28, 1.0],
        CoordinateKind::Harmonic => [0.95, 0.18, 0.15, 1.0],
    }
}

/// `colour` faded towards the background by `amount` in 0..1 (cages of other levels).
pub fn dim(colour: Rgba, amount: f32) -> Rgba {
    let [r, g, b, a] = colour;
    let [br, bg, bb, _] = BACKGROUND_BOTTOM;
    let t = amount.clamp(0.0, 1.0);
    [r + (br - r) * t, g + (bg - g) * t, b + (bb - b) * t, a]
}

/// Stops of the influence ramp: 0 is blue (the join transformation fully applied), 1 is red
/// (the cage transformation T fully applied), as in the paper's figures.
pub const RAMP: [(f32, Rgba); 5] = [
    (0.0, [0.10, 0.22, 0.95, 1.0]),
    (0.25, [0.15, 0.65, 0.95, 1.0]),
    (0.5, [0.92, 0.92, 0.92, 1.0]),
    (0.75, [0.98, 0.62, 0.20, 1.0]),
    (1.0, [0.90, 0.10, 0.10, 1.0]),
];

/// The ramp's colour at `t` in 0..1 (clamped); [`NO_VALUE`] for NaN.
pub fn ramp(t: f32) -> Rgba {
    if t.is_nan() {
        return NO_VALUE;
    }
    let t = t.clamp(0.0, 1.0);
    if t >= 1.0 {
        return RAMP[RAMP.len() - 1].1;
    }
    for pair in RAMP.windows(2) {
        let ((t0, c0), (t1, c1)) = (pair[0], pair[1]);
        if t <= t1 {
            let s = (t - t0) / (t1 - t0);
            return std::array::from_fn(|i| c0[i] + (c1[i] - c0[i]) * s);
        }
    }
    RAMP[RAMP.len() - 1].1
}

/// 8-bit sRGB-ish packing of a colour (the renderer's vertex colour format).
pub fn to_u8(colour: Rgba) -> [u8; 4] {
    colour.map(|c| (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ramp_runs_from_blue_to_red_continuously() {
        assert_eq!(ramp(0.0), RAMP[0].1);
        assert_eq!(ramp(1.0), RAMP[4].1);
        assert_eq!(ramp(f32::NAN), NO_VALUE);
        let mut previous = ramp(0.0);
        for i in 1..=1000 {
            let c = ramp(i as f32 / 1000.0);
            let jump: f32 = c.iter().zip(&previous).map(|(a, b)| (a - b).abs()).sum();
            assert!(jump < 0.02, "jump {jump} at {i}");
            previous = c;
        }
        let [r, _, b, _] = ramp(0.0);
        assert!(b > r);
        let [r, _, b, _] = ramp(1.0);
        assert!(r > b);
    }
}
