//! Bind cost of the three coordinate systems (criterion, release profile).
//!
//! * MVC and GC: a 320-triangle star-shaped cage and 4,000 interior points, on 1 and 2 threads;
//!   throughput is in point·faces, so criterion's "elem/s" inverts to ns per point·face. The
//!   kernels use AVX2 + FMA where the CPU has them; `STARCAGES_SIMD=portable` measures the
//!   portable (SSE2) path.
//! * HC: an 8-vertex cube cage around 10,000 points at the default resolution (the setting of
//!   the Blender Mesh Deform comparison), on all threads.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use starcages_core::cage::shapes;
use starcages_core::{BindControl, BindSettings, Cage, CoordinateKind, bind};

/// Icosahedron subdivided twice (162 vertices, 320 faces), radially bumped: non-convex.
fn bumpy_sphere() -> Cage {
    let (positions, faces) = shapes::icosphere_soup(2);
    let positions = positions
        .into_iter()
        .map(|p| p * (1.0 + 0.15 * (3.0 * p.x).sin() * (2.0 * p.y).cos()))
        .collect();
    Cage::from_triangles(positions, &faces).expect("valid bumpy sphere")
}

/// Deterministic points in the ball of radius `r` (a Fibonacci-like spiral).
fn points_in_ball(count: usize, r: f64) -> Vec<DVec3> {
    (0..count)
        .map(|i| {
            let t = (i as f64 + 0.5) / count as f64;
            let z = 1.0 - 2.0 * t;
            let phi = i as f64 * 2.399_963_229_728_653;
            let rad = r * ((i * 7919) % count) as f64 / count as f64;
            let s = (1.0 - z * z).sqrt();
            DVec3::new(s * phi.cos(), s * phi.sin(), z) * rad
        })
        .collect()
}

fn bench_mvc_gc(c: &mut Criterion) {
    eprintln!(
        "SIMD backend: {} (set {}=portable for the portable one)",
        starcages_core::coords::lane_backend(),
        starcages_core::coords::SIMD_ENV
    );
    let cage = bumpy_sphere();
    let points = points_in_ball(4_000, 0.8);
    let mut group = c.benchmark_group("bind_per_point_face");
    group.sample_size(10);
    group.throughput(Throughput::Elements(
        (points.len() * cage.triangles().len()) as u64,
    ));
    for kind in [CoordinateKind::MeanValue, CoordinateKind::Green] {
        for threads in [1usize, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool");
            group.bench_with_input(
                BenchmarkId::new(kind.short_name(), format!("{threads}t")),
                &threads,
                |b, _| {
                    b.iter(|| {
                        pool.install(|| {
                            bind(
                                kind,
                                &cage,
                                &points,
                                &BindSettings::default(),
                                &BindControl::default(),
                            )
                        })
                        .expect("bind")
                    });
                },
            );
        }
    }
    group.finish();
}

fn bench_hc(c: &mut Criterion) {
    let cage = shapes::cuboid(DVec3::splat(-1.0), DVec3::splat(1.0));
    let points: Vec<DVec3> = points_in_ball(10_000, 0.95);
    let mut group = c.benchmark_group("hc_bind_cube_10k");
    group.sample_size(10);
    group.bench_function("default_resolution", |b| {
        b.iter(|| {
            bind(
                CoordinateKind::Harmonic,
                &cage,
                &points,
                &BindSettings::default(),
                &BindControl::default(),
            )
            .expect("bind")
        });
    });
    group.finish();
}

criterion_group!(benches, bench_mvc_gc, bench_hc);
criterion_main!(benches);
