# Type stubs of the meniscus package (the extension meniscus._meniscus and
# render() of __init__.py). Docstrings are on the objects themselves.
import os
from typing import Any, Iterator, Literal, Mapping, Sequence, Tuple, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str
DEMO_RADIUS: float

PathLike = Union[str, os.PathLike[str]]
# A frame: "position" (N x 3 float32) and attributes by name (float32 or int64, N or N x C).
Frame = dict[str, np.ndarray]
# Positions (N x 3, float32 or float64, C-contiguous) or a frame as read() returns it.
Particles = Union[npt.ArrayLike, Mapping[str, Any]]
Vec3 = Union[Sequence[float], npt.ArrayLike]
Box = Tuple[Vec3, Vec3]

class Camera(TypedDict, total=False):
    eye: Vec3
    target: Vec3
    fov: float
    near: float
    far: float
    azimuth: float
    elevation: float
    distance: float

class AutoCamera(TypedDict):
    eye: Tuple[float, float, float]
    target: Tuple[float, float, float]
    fov: float
    near: float
    far: float

class SettingInfo(TypedDict):
    option: str
    default: str
    unit: str
    group: str
    help: str

# Settings: `meniscus render`'s options by their Python names (settings()).
Setting = Union[bool, int, float, str, Sequence[float], Sequence[str], None]

def read(path: PathLike, allow_empty: bool = ...) -> Frame: ...
def sequence(spec: str) -> list[str]: ...
def demo() -> Frame: ...
def estimate_radius(particles: Particles, *, h_per_spacing: float = ...) -> float: ...
def write_png(path: PathLike, image: npt.NDArray[np.uint8], alpha: bool | None = ...) -> None: ...
def settings(command: Literal["render", "mesh", "simulate"] = ...) -> dict[str, SettingInfo]: ...
def auto_camera(particles: Particles, *, radius: float | None = ..., width: int = ..., height: int = ...,
                **settings: Setting) -> AutoCamera: ...

class Renderer:
    def __init__(self, width: int = ..., height: int = ..., backend: str = ..., **settings: Setting) -> None: ...
    @property
    def backend(self) -> str: ...
    @property
    def note(self) -> str: ...
    @overload
    def render(self, particles: Particles, *, radius: float | None = ..., camera: Camera | None = ...,
               aovs: Literal[False] = ..., velocity: npt.ArrayLike | None = ...,
               density: npt.ArrayLike | None = ..., id: npt.ArrayLike | None = ...,
               fluid: npt.ArrayLike | None = ..., color: npt.ArrayLike | None = ...,
               radii: npt.ArrayLike | None = ..., studio: Box | None = ...,
               frame: int | None = ...,
               background: Tuple[npt.ArrayLike, npt.ArrayLike] | None = ...) -> npt.NDArray[np.uint8]: ...
    @overload
    def render(self, particles: Particles, *, radius: float | None = ..., camera: Camera | None = ...,
               aovs: Literal[True], velocity: npt.ArrayLike | None = ...,
               density: npt.ArrayLike | None = ..., id: npt.ArrayLike | None = ...,
               fluid: npt.ArrayLike | None = ..., color: npt.ArrayLike | None = ...,
               radii: npt.ArrayLike | None = ..., studio: Box | None = ...,
               frame: int | None = ...,
               background: Tuple[npt.ArrayLike, npt.ArrayLike] | None = ...) -> Tuple[npt.NDArray[np.uint8], dict[str, npt.NDArray[np.float32]]]: ...

@overload
def render(particles: Particles, radius: float | None = ..., *, width: int | None = ..., height: int | None = ...,
           camera: Camera | None = ..., filter: str | None = ..., backend: str = ..., aovs: Literal[False] = ...,
           velocity: npt.ArrayLike | None = ..., density: npt.ArrayLike | None = ...,
           id: npt.ArrayLike | None = ..., fluid: npt.ArrayLike | None = ..., color: npt.ArrayLike | None = ...,
           radii: npt.ArrayLike | None = ..., studio: Box | None = ..., frame: int | None = ...,
           background: str | Tuple[npt.ArrayLike, npt.ArrayLike] | None = ...,
           **settings: Setting) -> npt.NDArray[np.uint8]: ...
@overload
def render(particles: Particles, radius: float | None = ..., *, width: int | None = ..., height: int | None = ...,
           camera: Camera | None = ..., filter: str | None = ..., backend: str = ..., aovs: Literal[True],
           velocity: npt.ArrayLike | None = ..., density: npt.ArrayLike | None = ...,
           id: npt.ArrayLike | None = ..., fluid: npt.ArrayLike | None = ..., color: npt.ArrayLike | None = ...,
           radii: npt.ArrayLike | None = ..., studio: Box | None = ..., frame: int | None = ...,
           background: str | Tuple[npt.ArrayLike, npt.ArrayLike] | None = ...,
           **settings: Setting) -> Tuple[npt.NDArray[np.uint8], dict[str, npt.NDArray[np.float32]]]: ...

@overload
def mesh(particles: Particles, *, radius: float | None = ..., field: str = ..., cube_size: float = ...,
         iso: float = ..., support: float | None = ..., block: int = ..., threads: int = ...,
         normals: Literal[True] = ..., h_per_spacing: float = ..., interpolate: None = ...
         ) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.uint32], npt.NDArray[np.float32]]: ...
@overload
def mesh(particles: Particles, *, radius: float | None = ..., field: str = ..., cube_size: float = ...,
         iso: float = ..., support: float | None = ..., block: int = ..., threads: int = ...,
         normals: Literal[False], h_per_spacing: float = ..., interpolate: None = ...
         ) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.uint32]]: ...
@overload
def mesh(particles: dict[str, Any], *, radius: float | None = ..., field: str = ..., cube_size: float = ...,
         iso: float = ..., support: float | None = ..., block: int = ..., threads: int = ...,
         normals: Literal[True] = ..., h_per_spacing: float = ..., interpolate: Sequence[str]
         ) -> Tuple[npt.NDArray[np.float32], npt.NDArray[np.uint32], npt.NDArray[np.float32],
                    dict[str, npt.NDArray[np.float32]]]: ...
def write_mesh(path: PathLike, vertices: npt.ArrayLike, faces: npt.ArrayLike, normals: npt.ArrayLike | None = ...,
               attributes: dict[str, npt.ArrayLike] | None = ...) -> None: ...

class Simulation:
    def __iter__(self) -> Iterator[dict[str, Any]]: ...
    def __next__(self) -> dict[str, Any]: ...  # a Frame plus "time" (float, seconds)
    def __len__(self) -> int: ...
    @property
    def radius(self) -> float: ...
    @property
    def particles(self) -> int: ...
    @property
    def domain(self) -> Tuple[Tuple[float, float, float], Tuple[float, float, float]]: ...

def simulate(scene: Union[PathLike, Mapping[str, Any]], *, duration: float | None = ..., fps: float | None = ...,
             radius: float | None = ..., solver: str | None = ...) -> Simulation: ...
