"""Ctrl-C (SIGINT) during rigfit.fit stops it within a generation, keeps the
checkpoint, and the resumed fit equals an uninterrupted one."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import rigfit

SCRIPT = textwrap.dedent("""
    import signal, sys, rigfit
    # As in a terminal or Jupyter, even where the test runner was started
    # with SIGINT ignored (a background job of a non-interactive shell).
    signal.signal(signal.SIGINT, signal.default_int_handler)
    c = rigfit.Campaign.from_json(sys.argv[1])
    def progress(p):
        if p["stage"] == "ga" and p["generation"] == 3:
            print("generation 3", flush=True)
    try:
        rigfit.fit(c, out=sys.argv[2], backend="cpu", progress=progress)
    except rigfit.Interrupted as e:
        print("interrupted", e.checkpoint, flush=True)
        print(e, flush=True)
        sys.exit(130)
    print("finished", flush=True)
""")


def _slow(bearing):
    raw = json.loads(bearing.read_text())
    raw["search"] = {"population": 256, "generations": 40, "seed": 9, "checkpoint_every": 1}
    bearing.write_text(json.dumps(raw))
    return bearing


def test_sigint_stops_the_fit_keeps_the_checkpoint_and_resumes_to_the_same_result(bearing, tmp_path):
    campaign = _slow(bearing)
    out = tmp_path / "job"
    p = subprocess.Popen([sys.executable, "-c", SCRIPT, str(campaign), str(out)],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = p.stdout.readline()
    assert line.startswith("generation 3"), (line, p.stderr.read())
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    rest, err = p.communicate(timeout=30)
    took = time.monotonic() - sent
    assert p.returncode == 130, (rest, err)
    assert rest.startswith("interrupted " + str(out)), rest
    # The hint repeats the settings the job was given, so following it resumes.
    assert f"rigfit.fit(campaign, out={str(out)!r}, resume=True, backend='cpu')" in rest, rest
    print(f"stopped {took:.2f} s after SIGINT")
    assert took < 2.0, f"took {took:.2f} s to stop"
    assert (out / "checkpoint.json").is_file()

    c = rigfit.Campaign.from_json(campaign)
    resumed = rigfit.fit(c, out=out, resume=True, backend="cpu")
    assert not (out / "checkpoint.json").exists()
    whole = rigfit.fit(c, backend="cpu")
    a, b = json.loads(resumed.files["result.json"]), json.loads(whole.files["result.json"])
    assert a["params"] == b["params"]
    assert [p["std_error"] for p in a["parameters"] if p["free"]] == \
        [p["std_error"] for p in b["parameters"] if p["free"]]
    assert resumed.files["hx.csv"] == whole.files["hx.csv"]
