"""rigfit: calibrate lumped mass-spring-damper models of mechanical test rigs
to measured records, from numpy, pandas and Jupyter.

The package binds the rigfit library (the same code as the ``rigfit``
command line): :class:`Campaign` objects, :func:`fit` (the job ``rigfit run``
runs), :func:`simulate` and :meth:`Campaign.objective` (the ensemble
integrator as a function), :func:`load_result`, and the classical
identification in :mod:`rigfit.identify`.
"""

from . import identify
from ._rigfit import __version__
from .campaign import Campaign, shipped_rigs
from .ensemble import Objective, simulate
from .identify import arx, fit_specimen, frf, idim, impedance, nimiso, rfs, ringdown, sensitivity
from .errors import (ArgumentTypeError, CampaignError, DataError, DeviceError, Error,
                     GpuFallbackWarning, Interrupted)
from .fitting import fit
from .params import Parameter, Parameters
from .result import ExperimentResult, FitResult, load_result
from .sweep import sweep

__all__ = [
    "ArgumentTypeError", "Campaign", "CampaignError", "DataError", "DeviceError", "Error",
    "ExperimentResult",
    "FitResult", "GpuFallbackWarning", "Interrupted", "Objective", "Parameter", "Parameters",
    "__version__", "arx", "fit", "fit_specimen", "frf", "idim", "identify", "impedance",
    "load_result", "nimiso", "rfs", "ringdown", "sensitivity", "shipped_rigs", "simulate",
    "sweep",
]
