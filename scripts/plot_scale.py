#!/usr/bin/env python3
"""Plot `starcages-bench --scale MESH --json` output: bind time and peak memory against
mesh vertices, for *Cages, the single MVC cage and (where measured) Blender's Mesh Deform.

Usage (matplotlib in a throw-away venv, never a project dependency):
    starcages-bench --scale ../shared/meshes/armadillo.obj --blender VENV/bin/python \\
        --json > scale.json
    VENV/bin/python scripts/plot_scale.py scale.json docs/images/bind_scale.png
"""

import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def finish(axes, unit, title):
    """Log-log axes over mesh vertices, with a grid and the legend."""
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("mesh vertices")
    axes.set_ylabel(unit)
    axes.set_title(title)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(loc="upper left", fontsize="small")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    with open(sys.argv[1], encoding="utf-8") as f:
        sizes = json.load(f)
    vertices = [s["mesh_vertices"] for s in sizes]
    figure, (time_axes, memory_axes) = plt.subplots(1, 2, figsize=(11, 4.2))

    time_axes.plot(vertices, [s["stars"]["seconds"] for s in sizes], "o-", label="*Cages bind")
    time_axes.plot(
        vertices, [s["single_mvc"]["seconds"] for s in sizes], "s--", label="single MVC bind"
    )
    blender = [(s["mesh_vertices"], s["blender"]) for s in sizes if s.get("blender")]
    if blender:
        time_axes.plot(
            [v for v, _ in blender],
            [b["bind_seconds"] for _, b in blender],
            "^-",
            label="Blender Mesh Deform bind (precision 5)",
        )
    finish(time_axes, "seconds", "Bind time (3×3×3 grid, default settings)")

    memory_axes.plot(
        vertices, [s["stars"]["peak_mb"] for s in sizes], "o-", label="*Cages bind, peak heap"
    )
    memory_axes.plot(
        vertices,
        [s["mesh_mb"] + s["stars"]["stored_mb"] for s in sizes],
        "k:",
        label="mesh + stored binding",
    )
    memory_axes.plot(
        vertices,
        [s["single_mvc"]["peak_mb"] for s in sizes],
        "s--",
        label="single MVC bind, peak heap",
    )
    if blender:
        memory_axes.plot(
            [v for v, _ in blender],
            [b["bind_rss_mb"] for _, b in blender],
            "^-",
            label="Blender, resident memory the bind added",
        )
    finish(memory_axes, "MB", "Bind memory")

    figure.tight_layout()
    figure.savefig(sys.argv[2], dpi=110)


main()
