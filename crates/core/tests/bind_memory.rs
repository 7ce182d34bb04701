//! The bind's memory is bounded (issue 29): its peak heap, above what was held before it,
//! stays within twice what it keeps (the mesh and the stored binding), so a mesh ten times
//! larger needs ten times the memory, not forty. Its own test binary: the counting allocator
//! must be the process's global one. A regression (a table over all points at once, rows kept
//! unpacked) fails here, not only in `bench --scale`.

use peakmem_alloc::{INSTRUMENTED_SYSTEM, PeakMemAlloc, PeakMemAllocTrait as _};
use starcages_core::BindControl;
use starcages_core::generate::demo::demo_scene;
use starcages_core::generate::{AutocageOptions, autocage};
use starcages_core::scene::{MeshSource, Scene, SceneSettings};
use starcages_core::star::StarBinding;

#[global_allocator]
static ALLOCATOR: &PeakMemAlloc<std::alloc::System> = &INSTRUMENTED_SYSTEM;

#[test]
fn a_bind_s_peak_memory_stays_within_twice_the_mesh_and_the_binding_it_keeps() {
    // The egg subdivided to about 60k vertices in the automatic 3×3×3 grid, default settings
    // (harmonic joins where the grid's joins are concave): a mid-size mesh.
    let egg = demo_scene("egg", 1.0).unwrap().mesh;
    let mesh = egg.subdivided(3).unwrap();
    assert!(mesh.welded_positions().len() > 40_000);
    let cages = autocage(&mesh, &AutocageOptions::default());
    let scene = Scene::new(MeshSource::Embedded, mesh, cages, SceneSettings::default());
    starcages_core::coords::clear_harmonic_cache();
    let control = BindControl::default();
    ALLOCATOR.reset_peak_memory();
    let binding = StarBinding::bind_scene(&scene, &control).unwrap();
    let peak = ALLOCATOR.get_peak_memory();
    let bound = 2 * (binding.byte_size() + scene.mesh.byte_size());
    assert!(
        peak <= bound,
        "the bind's peak heap is {:.1} MB, over twice the mesh and the binding ({:.1} MB)",
        peak as f64 / 1e6,
        bound as f64 / 1e6
    );
}
