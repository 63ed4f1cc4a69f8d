"""Type stubs of the clino package (units in the docstrings of __init__.py)."""

from __future__ import annotations

import os
from typing import Any, Dict, Iterable, List, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike[str]]
ArrayLike = npt.ArrayLike
F64 = npt.NDArray[np.float64]
Stamps = Literal["recover", "as-given"]

G0: float
STATUS_NAMES: Tuple[str, ...]

class ClinoError(ValueError):
    kind: str
    message: str
    file: Optional[str]
    line: Optional[int]
    column: Optional[str]

class Calibration:
    def __init__(self) -> None: ...
    @staticmethod
    def load(path: str) -> Calibration: ...
    @staticmethod
    def from_toml(text: str) -> Calibration: ...
    def to_toml(self) -> str: ...
    def to_json(self) -> str: ...
    def save(self, path: str) -> None: ...
    extrapolate: bool
    def apply(
        self, gyr: F64, acc: F64, mag: Optional[F64] = None, temp_c: Optional[F64] = None
    ) -> Tuple[F64, F64, Optional[F64]]: ...

def fuse(
    gyr: ArrayLike,
    acc: ArrayLike,
    rate: Optional[float] = None,
    t: Optional[ArrayLike] = None,
    filter: str = "dynamic",
    lever_arm: Optional[Sequence[float]] = None,
    calibration: Union[Calibration, PathLike, None] = None,
    offline: bool = False,
    *,
    temp_c: Optional[ArrayLike] = None,
    gyro_range: Optional[float] = None,
    acc_range: Optional[float] = None,
    stamps: Stamps = "recover",
    **params: Any,
) -> F64: ...
def fuse_full(
    gyr: ArrayLike,
    acc: ArrayLike,
    rate: Optional[float] = None,
    t: Optional[ArrayLike] = None,
    filter: str = "dynamic",
    lever_arm: Optional[Sequence[float]] = None,
    calibration: Union[Calibration, PathLike, None] = None,
    offline: bool = False,
    *,
    temp_c: Optional[ArrayLike] = None,
    gyro_range: Optional[float] = None,
    acc_range: Optional[float] = None,
    stamps: Stamps = "recover",
    **params: Any,
) -> Dict[str, Any]: ...

class Filter:
    def __init__(
        self,
        Ts: Optional[float] = None,
        *,
        rate: Optional[float] = None,
        filter: Optional[str] = None,
        lever_arm: Optional[Sequence[float]] = None,
        calibration: Union[Calibration, PathLike, None] = None,
        gyro_range: Optional[float] = None,
        acc_range: Optional[float] = None,
        stamps: Stamps = "recover",
        **params: Any,
    ) -> None: ...
    def update(
        self, gyr: ArrayLike, acc: ArrayLike, t: Optional[float] = None, temp_c: Optional[float] = None
    ) -> Optional[F64]: ...
    def update_batch(
        self, gyr: ArrayLike, acc: ArrayLike, t: Optional[ArrayLike] = None, temp_c: Optional[ArrayLike] = None
    ) -> Dict[str, Any]: ...
    def updateBatch(
        self, gyr: ArrayLike, acc: ArrayLike, t: Optional[ArrayLike] = None, temp_c: Optional[ArrayLike] = None
    ) -> Dict[str, Any]: ...
    def getQuat6D(self) -> Optional[F64]: ...
    @property
    def quat(self) -> Optional[F64]: ...
    @property
    def counts(self) -> Dict[str, int]: ...
    @property
    def label(self) -> str: ...
    def reset(self) -> None: ...

class Poisson(Filter): ...
class Complementary(Filter): ...
class Mahony(Filter): ...
class Madgwick(Filter): ...
class Dynamic(Filter): ...

def filter_help() -> str: ...
def evaluate(
    paths: Union[PathLike, Sequence[PathLike]],
    filter: str = "all",
    *,
    lever_arm: Optional[Sequence[float]] = None,
    offline: bool = False,
    gyro_range: Optional[float] = None,
    acc_range: Optional[float] = None,
    stamps: Stamps = "recover",
    jobs: Optional[int] = None,
    gyro_unit: str = "rad/s",
    accel_unit: str = "m/s2",
    rate: Optional[float] = None,
    g: float = ...,
    as_frame: bool = False,
    **params: Any,
) -> Any: ...
def score(estimate: ArrayLike, reference: ArrayLike, movement: ArrayLike) -> Dict[str, Any]: ...
def inclination_error(estimate: ArrayLike, reference: ArrayLike) -> F64: ...
def read_recording(
    path: PathLike,
    *,
    gyro_unit: str = "rad/s",
    accel_unit: str = "m/s2",
    rate: Optional[float] = None,
    g: float = ...,
    as_frame: bool = False,
) -> Any: ...
def read_table(path: PathLike, text_columns: Iterable[str] = ("status",), as_frame: bool = False) -> Any: ...
def write_table(path: PathLike, table: Any) -> int: ...
def summarize(
    source: Any,
    filter: str = "dynamic",
    *,
    name: Optional[str] = None,
    lever_arm: Optional[Sequence[float]] = None,
    offline: bool = False,
    calibration: Union[Calibration, PathLike, None] = None,
    gyro_range: Optional[float] = None,
    acc_range: Optional[float] = None,
    stamps: Stamps = "recover",
    gyro_unit: str = "rad/s",
    accel_unit: str = "m/s2",
    rate: Optional[float] = None,
    g: float = ...,
    **params: Any,
) -> Dict[str, Any]: ...
def calibrate(
    kind: str,
    path: PathLike,
    model: str = "mwd12",
    *,
    g: float = ...,
    field_ut: Optional[float] = None,
    window_s: float = 0.5,
    min_pose_s: float = 1.0,
    accel_calibration: Union[Calibration, PathLike, None] = None,
) -> Tuple[Dict[str, Any], Calibration]: ...
def survey(
    path: PathLike, declination_deg: float = 0.0, calibration: Union[Calibration, PathLike, None] = None, as_frame: bool = False
) -> Any: ...
def minimum_curvature(md_m: ArrayLike, inclination_deg: ArrayLike, azimuth_deg: ArrayLike) -> List[Dict[str, float]]: ...
def sine_fit(
    t: ArrayLike, y: ArrayLike, freq_hz: Optional[float] = None, trend_order: int = 0, estimate_freq: bool = False
) -> Dict[str, Any]: ...
def simulate_static(preset: str = "mpu6050", rate_hz: float = 100.0, duration_s: float = 60.0, seed: int = 1) -> Dict[str, F64]: ...
def static_test(t: ArrayLike, gyr: ArrayLike, acc: ArrayLike, filter: Optional[str] = None, settle_s: float = 5.0) -> Dict[str, Any]: ...
def testbench_analyze(path: PathLike, excitation: str = "conical", freq_hz: Optional[float] = None, skip_s: float = 0.0) -> Dict[str, Any]: ...
def allan_deviation(y: ArrayLike, rate_hz: float, per_decade: int = 10, as_frame: bool = False) -> Any: ...
def allan(path: PathLike, gaps: str = "refuse") -> Dict[str, Any]: ...
def redundancy_diagnose(path: PathLike, **kw: Any) -> Dict[str, Any]: ...
