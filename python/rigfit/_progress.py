"""The bar ``progress=True`` draws (``rigfit.fit``, ``rigfit.sweep``):
tqdm's, or a plain line where tqdm is not installed."""

import warnings


def progress_bar():
    """``tqdm.auto.tqdm``, or without tqdm (``pip install "rigfit[progress]"``
    brings it) :class:`_TextBar`, a plain line on stderr rewritten in place."""
    with warnings.catch_warnings():
        # Jupyter without ipywidgets: tqdm.auto falls back to a text bar and
        # says so once; the text bar is what the caller gets either way.
        warnings.simplefilter("ignore")
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return _TextBar
    return tqdm


class _TextBar:
    """The little of tqdm's bar that :func:`progress_bar`'s callers use, as one line on
    stderr rewritten in place (at most ten times a second)."""

    def __init__(self, total=None, desc="", unit="it"):
        import sys
        import time
        self._out, self._clock = sys.stderr, time.monotonic
        self.total, self.desc, self.unit, self.n = total, desc, unit, 0
        self._postfix, self._shown, self._open = "", 0.0, True

    def set_postfix(self, refresh=False, **values):
        self._postfix = ", ".join(f"{k}={v}" for k, v in values.items())

    def refresh(self, final=False):
        now = self._clock()
        if not final and now - self._shown < 0.1:
            return
        self._shown = now
        of = f"/{self.total}" if self.total else ""
        tail = f" [{self._postfix}]" if self._postfix else ""
        self._out.write(f"\r{self.desc}: {self.n}{of} {self.unit}{tail}")
        self._out.flush()

    def close(self):
        if self._open:
            self._open = False
            self.refresh(final=True)
            self._out.write("\n")
            self._out.flush()
