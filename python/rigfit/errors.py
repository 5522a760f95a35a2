"""The exceptions rigfit raises.

Every message is one line, as the command line prints it: the campaign file,
the JSON path (or the data file and line), what was expected and what was
found.
"""


class Error(Exception):
    """A rigfit error: a job that failed after its input was accepted, or an
    internal error (a bug; the message says so)."""


class CampaignError(Error, ValueError):
    """A campaign, a setting or an argument that rigfit refuses."""


class ArgumentTypeError(Error, TypeError):
    """An argument of the wrong type (a str where a number is expected, a
    path where a :class:`rigfit.Campaign` is); the message names it."""


class DataError(Error, ValueError):
    """A measured record that rigfit refuses."""


class DeviceError(Error, RuntimeError):
    """The GPU is missing (where it was required) or failed."""


class Interrupted(KeyboardInterrupt):
    """A fit stopped by Ctrl-C (KeyboardInterrupt). ``checkpoint`` is the
    output folder holding the checkpoint (``None`` when the job was stopped
    before its first generation was complete): ``rigfit.fit(campaign,
    out=checkpoint, resume=True)`` continues it."""

    def __init__(self, message, checkpoint=None):
        super().__init__(message)
        self.checkpoint = checkpoint


class GpuFallbackWarning(UserWarning):
    """The GPU path was asked for with ``backend="auto"`` and the job runs on
    the CPU instead (no adapter, or the rig has no kernels)."""
