"""StarCages: *Cages (star-cages) deformation, numpy in and out.

Every array is in the mesh file's axes (`Scene.up`); meshes are welded (vertices at the same
position are one), as StarCages binds and deforms them. Errors are `StarCagesError` with the
command-line tool's one-line messages.
"""

from collections.abc import Callable, Sequence
from os import PathLike
from typing import Any, TypedDict

import numpy as np
import numpy.typing as npt

__version__: str

class StarCagesError(Exception):
    """A StarCages error: the message names the file, element and reason."""

class LeafCage(TypedDict):
    name: str
    kind: str
    h: float | None
    faces: list[list[int]]

class Control(TypedDict):
    name: str
    kind: str
    faces: list[list[int]]
    owns: list[int]
    pivot: list[float] | None
    joint: list[int]

class Key(TypedDict):
    frame: float
    pose: str
    interpolation: str
    h: dict[str, float]

class Operator(TypedDict):
    indptr: npt.NDArray[np.int64]
    indices: npt.NDArray[np.int32]
    data: npt.NDArray[np.float32]
    shape: tuple[int, int]
    rest_offsets: npt.NDArray[np.float32]

def read_mesh(path: str | PathLike[str]) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.uint32]]:
    """The welded vertices (n, 3) and triangles (m, 3) of a mesh file (OBJ, glTF, GLB, FBX,
    PLY, STL, OFF), in the file's axes."""

def demo(name: str, detail: float = 1.0) -> Scene:
    """A generated demo scene (`demo_names()`)."""

def demo_names() -> list[str]:
    """The names `demo` takes."""

def autorig(
    vertices: npt.ArrayLike,
    triangles: npt.ArrayLike,
    detail: int = 3,
    mirror: str | None = None,
    controls: bool = True,
    up: str = "z",
) -> Scene:
    """The auto rig of a mesh given as arrays (`up`: their up axis): leaf cages along its
    limbs and a control per segment; `mirror` is "x", "y", "z" (the arrays' axes) or "auto"."""

class Scene:
    @staticmethod
    def load(path: str | PathLike[str]) -> Scene:
        """A scene file (and the mesh file it names), checked as the CLI checks it."""
    def save(self, path: str | PathLike[str]) -> None:
        """Writes the scene file atomically."""
    @property
    def up(self) -> str:
        """The mesh file's up axis, "y" or "z": the axes of every array."""
    @property
    def mesh_vertices(self) -> npt.NDArray[np.float64]: ...
    @property
    def mesh_triangles(self) -> npt.NDArray[np.uint32]: ...
    @property
    def cage_vertices(self) -> npt.NDArray[np.float64]:
        """Every cage vertex (leaf and control cages) at rest, (k, 3)."""
    @property
    def pose(self) -> npt.NDArray[np.float64]:
        """The current pose's cage vertices."""
    @property
    def leaf_cages(self) -> list[LeafCage]: ...
    @property
    def controls(self) -> list[Control]:
        """The controls (internal cages), each with its pivot (joint) where it has one."""
    @property
    def poses(self) -> dict[str, npt.NDArray[np.float64]]: ...
    @property
    def keys(self) -> list[Key]: ...
    @property
    def fps(self) -> float: ...
    @property
    def frame_range(self) -> tuple[int, int]: ...
    def posed(
        self,
        edits: Sequence[str] = ...,
        pose: str | None = None,
        frame: float | None = None,
    ) -> npt.NDArray[np.float64]:
        """Cage positions of the rest pose, a named pose or a frame, with edits such as
        "leg.L.2: rotate 1 0 0 60" propagated down the controls (the CLI's --apply); the
        joints as the mitre leaves them (Binding.keep_joint_volumes settles them)."""
    def control_parents(self) -> dict[str, str | None]:
        """Each control's parent: the control that moves its cage vertices."""
    def posed_by_controls(
        self, transforms: dict[str, npt.ArrayLike], offsets: npt.ArrayLike | None = None
    ) -> npt.NDArray[np.float64]:
        """Cage positions with each named control's cage moved by its 4×4 rest-to-posed
        transform (parents first, propagated down to the leaf cage vertices), then hand moves
        `offsets` ((k, 3)) on top."""
    @property
    def default_h(self) -> float: ...
    def with_default_h(self, h: float) -> Scene:
        """A copy with another default h."""
    def with_cage(self, name: str, kind: str | None = None, h: float | None = None, scene_h: bool = False) -> Scene:
        """A copy in which a leaf cage uses other coordinates ("mvc", "hc", "gc") and/or its own h."""
    def with_pose(self, cage_positions: npt.ArrayLike) -> Scene:
        """A copy whose current pose is `cage_positions`."""
    def to_scene_axes(self, points: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Points of the file's axes in StarCages' Z-up scene coordinates (the operator's)."""
    def to_file_axes(self, points: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """Scene coordinates back in the file's axes."""
    def bind(self, progress: Callable[[float], Any] | None = None) -> Binding:
        """Binds the mesh to the cages with the GIL released; `progress(fraction)` is called
        before and while it runs, and returning False (or raising) cancels it."""

class Binding:
    @property
    def vertex_count(self) -> int: ...
    @property
    def dof_count(self) -> int: ...
    @property
    def nonzeros(self) -> int: ...
    def deform(self, cage_positions: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """The welded mesh for every cage vertex at `cage_positions` ((k, 3))."""
    def keep_joint_volumes(
        self, cage_positions: npt.ArrayLike, keep: list[int] | None = None
    ) -> npt.NDArray[np.float64]:
        """Cage positions with every bent joint's ring scaled so that the mesh around it
        keeps its rest volume (as the CLI's --apply and the editor pose); `keep` lists cage
        vertices (moved by hand) to leave alone."""
    def deform_frame(self, frame: float) -> npt.NDArray[np.float64]:
        """The welded mesh at an animation frame (keys interpolated, keyed h applied)."""
    def dofs(self, cage_positions: npt.ArrayLike) -> npt.NDArray[np.float32]:
        """The operator's degrees of freedom (scene axes) for cage positions."""
    def operator(self) -> Operator:
        """S as CSR arrays for scipy.sparse.csr_matrix((data, indices, indptr), shape=shape);
        the mesh (scene axes) is S @ dofs + rest_offsets."""
    def bake(
        self,
        path: str | PathLike[str],
        start: int | None = None,
        end: int | None = None,
    ) -> int:
        """Bakes the animation into a PC2 or MDD point cache in the mesh file's layout and
        axes, as `starcages-cli bake`; returns the number of samples."""
