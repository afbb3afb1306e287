"""Type stubs of the compiled module (`bcifs._bcifs`)."""

import os
from fractions import Fraction
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

__version__: str

class BcifsError(ValueError):
    """What bcifs refuses, with the library's message."""

class Mesh:
    """A mesh as numpy arrays."""

    vertices: npt.NDArray[np.floating[Any]]
    """(n, 3) positions (float64, or float32 from `mesh(dtype=np.float32)`)."""
    faces: Union[npt.NDArray[np.int64], list[npt.NDArray[np.int64]]]
    """(m, k) corner indices when every face has k corners, else one array per face."""
    edges: npt.NDArray[np.int64]
    """(e, 2) segments of curves."""
    normals: Optional[npt.NDArray[np.floating[Any]]]
    """(n, 3) unit vertex normals, when the output has them (the vertices' dtype)."""
    colours: Optional[npt.NDArray[np.uint8]]
    """(n, 3) RGB vertex colours, when the output has them."""
    uv: Optional[npt.NDArray[np.float64]]
    """(t, 2) texture coordinates, when the output has them (face-varying: see `uv_faces`)."""
    uv_faces: Optional[Union[npt.NDArray[np.int64], list[npt.NDArray[np.int64]]]]
    """Shaped as `faces`: the index into `uv` of every corner."""
    face_sources: Optional[npt.NDArray[np.int64]]
    """(m,) the input face each face comes from (`subdivide(..., face_data=...)`)."""
    face_data: Optional[dict[str, npt.NDArray[Any]]]
    """The `face_data` given to `subdivide`, each face's rows from its source face."""
    def to_trimesh(self) -> Any:
        """A trimesh `Trimesh`, `Path3D` or `PointCloud` (trimesh must be installed)."""
    def to_open3d(self) -> Any:
        """An Open3D `TriangleMesh`, `LineSet` or `PointCloud` (Open3D must be installed)."""

class Design:
    """An automaton with its model."""

    @staticmethod
    def from_toml(text: str) -> Design: ...
    def to_toml(self) -> str: ...
    @property
    def name(self) -> str: ...
    @property
    def parameters(self) -> list[str]: ...
    def ranges(self) -> list[dict[str, Any]]: ...
    def solve(self) -> dict[str, Any]: ...
    def check(self, **params: float) -> dict[str, Any]: ...
    def _repr_png_(self) -> bytes: ...
    def mesh(
        self,
        depth: Optional[int] = None,
        tolerance: Optional[float] = None,
        uv: Optional[bool] = None,
        force: Optional[bool] = None,
        thickness: Optional[float] = None,
        dtype: Optional[npt.DTypeLike] = None,
        colour: Optional[str] = None,
        palette: Optional[str] = None,
        **params: float,
    ) -> Mesh: ...
    def print_report(
        self,
        depth: Optional[int] = None,
        tolerance: Optional[float] = None,
        thickness: Optional[float] = None,
        print_size: Optional[float] = None,
        print_scale: Optional[float] = None,
        nozzle: Optional[float] = None,
        **params: float,
    ) -> dict[str, Any]: ...
    def points(self, samples: int, seed: Optional[int] = None, **params: float) -> npt.NDArray[np.float64]: ...
    def density(
        self,
        samples: int,
        size: Optional[tuple[int, int]] = None,
        seed: Optional[int] = None,
        palette: Optional[str] = None,
        **params: float,
    ) -> npt.NDArray[np.uint8]: ...
    def render(
        self,
        path: Union[str, os.PathLike[str]],
        progress: Optional[Callable[[int, int], Any]] = None,
        *,
        # The keys of `option_keys()`, in its order (the library's one description of them).
        params: Optional[dict[str, Union[float, str]]] = None,
        depth: Optional[int] = None,
        tolerance: Optional[float] = None,
        samples: Optional[int] = None,
        seed: int = 1,
        probs: Optional[dict[str, Union[float, str]]] = None,
        drop: Optional[Sequence[str]] = None,
        force: bool = False,
        threads: Optional[int] = None,
        memory_mib: int = 4096,
        max_output_gib: float = 4.0,
        size: tuple[int, int] = (800, 800),
        view: tuple[float, float] = (30.0, 35.0),
        transparent: bool = False,
        palette: Optional[str] = None,
        colour: Optional[str] = None,
        colours: Optional[dict[str, float]] = None,
        colour_speed: float = 0.5,
        brightness: float = 1.0,
        gamma: float = 2.2,
        supersample: int = 1,
        vibrancy: float = 1.0,
        blur: float = 0.0,
        blur_curve: float = 0.4,
        background: Optional[str] = None,
        uv: bool = False,
        up: str = "auto",
        ascii: bool = False,
        precision: Optional[int] = None,
        dedup: bool = False,
        thickness: Optional[float] = None,
        print_size: Optional[float] = None,
        print_scale: Optional[float] = None,
        nozzle: float = 0.4,
        allow_non_manifold: bool = False,
        # Python's own: the tone keys as one dict.
        tone: Optional[dict[str, Union[float, str]]] = None,
        **options: float,
    ) -> dict[str, Any]: ...

def load(name_or_path: Union[str, os.PathLike[str]], scheme: Optional[str] = None) -> Design: ...
def dimension(design: Design, **params: float) -> dict[str, Any]: ...
def topology(design: Design, depth: int = 3, **params: float) -> dict[str, Any]: ...
def pattern(
    cell: str,
    split: Union[int, str, Sequence[int]],
    keep: Optional[Union[str, Sequence[int], Sequence[bool]]] = None,
    degree: int = 2,
    name: str = "pattern",
    at: Optional[Union[str, Sequence[Union[float, str, Fraction]]]] = None,
    basis: str = "bezier",
) -> Design: ...
def polyhedral_lace(
    polyhedron: Union[str, os.PathLike[str], Sequence[Sequence[int]]],
    face: int = 0,
    name: Optional[str] = None,
) -> Design: ...
def lacunarity(design: Design, depth: Optional[int] = None, **params: float) -> dict[str, Any]: ...
def subdivide(
    vertices: npt.ArrayLike,
    faces: Union[npt.ArrayLike, Sequence[Sequence[int]]],
    scheme: str,
    depth: int,
    net: bool = False,
    uv: Optional[npt.ArrayLike] = None,
    uv_faces: Optional[Union[npt.ArrayLike, Sequence[Sequence[int]]]] = None,
    triangulate: bool = False,
    face_data: Optional[Mapping[str, npt.ArrayLike]] = None,
    **weights: float,
) -> Mesh: ...
def analyze_curve(design: Design, **params: Union[float, int, str, Fraction]) -> dict[str, Any]: ...
def fit(
    design: Design,
    target: Optional[Union[str, os.PathLike[str], npt.ArrayLike, Mesh, Any]] = None,
    dimension: Optional[float] = None,
    angle: Optional[float] = None,
    porosity: Optional[float] = None,
    depth: Optional[int] = None,
    starts: int = 4,
    progress: Optional[Callable[[int, int], Any]] = None,
    start: Optional[Sequence[float]] = None,
    free_pose: bool = False,
    control_points: bool = False,
) -> tuple[Design, dict[str, Any]]: ...
def fit_starts(
    design: Design,
    target: Optional[Union[str, os.PathLike[str], npt.ArrayLike, Mesh, Any]] = None,
    dimension: Optional[float] = None,
    angle: Optional[float] = None,
    porosity: Optional[float] = None,
    depth: Optional[int] = None,
    starts: int = 4,
) -> tuple[list[list[float]], list[list[float]], bool]: ...

REGIONS: list[str]
"""The regions of a region sweep, by code."""

class Builder:
    """The checked builder: a design made in code, checked as a whole by `build()`."""

    def __init__(self, name: str) -> None: ...
    @staticmethod
    def of(design: Design) -> Builder: ...
    def description(self, text: str) -> Builder: ...
    def doc(self, text: str) -> Builder: ...
    def state(self, name: str, dim: int, kind: str) -> Builder: ...
    def unknown(self, name: str, source: str, target: str) -> Builder: ...
    def matrix(self, name: str, source: str, target: str, rows: Any) -> Builder: ...
    def select(self, name: str, source: str, target: str, select: Sequence[int]) -> Builder: ...
    def constraint(self, group: str, equation: str) -> Builder: ...
    def adjacency(self, equation: str) -> Builder: ...
    def incidence(self, equation: str) -> Builder: ...
    def name_entry(self, name: str, entry: str, default: Optional[Union[float, str, Fraction]] = None) -> Builder: ...
    def parameter(self, name: str, default: Optional[Union[float, str, Fraction]] = None) -> Builder: ...
    def default(self, name: str, value: Union[float, str, Fraction]) -> Builder: ...
    def model(
        self,
        root: str,
        points: Sequence[Sequence[float]],
        layout: str = "single",
        roots: Optional[Sequence[str]] = None,
        step: Optional[int] = None,
        grid: Optional[tuple[int, int]] = None,
        net: Optional[Sequence[Sequence[int]]] = None,
        patches: Optional[Sequence[Sequence[int]]] = None,
        y_up: bool = False,
    ) -> Builder: ...
    def build(self) -> Design: ...
def map_colours(values: npt.ArrayLike, what: str = "verdict") -> npt.NDArray[np.uint8]: ...
def option_keys() -> list[dict[str, Any]]: ...
def profile(name: str) -> dict[str, Any]: ...
def sweep_rows(
    toml: str,
    x: tuple[str, float, float, int],
    y: tuple[str, float, float, int],
    rows: tuple[int, int],
    what: str = "verdict",
    thorough: bool = False,
) -> npt.NDArray[Any]: ...
