from . import identify as identify
from ._rigfit import __version__ as __version__
from .campaign import Campaign as Campaign, shipped_rigs as shipped_rigs
from .ensemble import Objective as Objective, simulate as simulate
from .errors import (
    ArgumentTypeError as ArgumentTypeError,
    CampaignError as CampaignError,
    DataError as DataError,
    DeviceError as DeviceError,
    Error as Error,
    GpuFallbackWarning as GpuFallbackWarning,
    Interrupted as Interrupted,
)
from .fitting import fit as fit
from .identify import (
    arx as arx,
    fit_specimen as fit_specimen,
    frf as frf,
    idim as idim,
    impedance as impedance,
    nimiso as nimiso,
    rfs as rfs,
    ringdown as ringdown,
    sensitivity as sensitivity,
)
from .params import Parameter as Parameter, Parameters as Parameters
from .result import (
    ExperimentResult as ExperimentResult,
    FitResult as FitResult,
    load_result as load_result,
)
from .sweep import sweep as sweep

__all__ = [
    "ArgumentTypeError", "Campaign", "CampaignError", "DataError", "DeviceError", "Error",
    "ExperimentResult",
    "FitResult", "GpuFallbackWarning", "Interrupted", "Objective", "Parameter", "Parameters",
    "__version__", "arx", "fit", "fit_specimen", "frf", "idim", "identify", "impedance",
    "load_result", "nimiso", "rfs", "ringdown", "sensitivity", "shipped_rigs", "simulate",
    "sweep",
]
