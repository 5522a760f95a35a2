"""A notebook's careless calls lose no file and leave nothing behind:
``FitResult.save`` by the rules of ``rigfit run``'s outputs (never through a
link, never over a file rigfit did not write, all or nothing), no temporary
job folder left after an error, a plain progress line without tqdm, a
campaign at a path that is not UTF-8."""

import json
import os
import shutil
import sys
import tempfile

import pytest

import rigfit

from conftest import CAMPAIGNS


@pytest.fixture(scope="module")
def fitted(tmp_path_factory):
    """A small fit of the shipped bearing campaign, once for the module."""
    folder = tmp_path_factory.mktemp("bearing")
    raw = json.loads((CAMPAIGNS / "bearing_2dof_synthetic.json").read_text())
    raw["search"] = {"population": 32, "generations": 3, "seed": 3}
    raw["solver"]["backend"] = "cpu"
    for x in raw["experiments"]:
        shutil.copy(CAMPAIGNS / x["data"]["file"], folder / x["data"]["file"])
    path = folder / "bearing.json"
    path.write_text(json.dumps(raw))
    return path, rigfit.fit(rigfit.Campaign.from_json(path), backend="cpu")


def _listing(folder):
    return sorted(os.listdir(folder))


def test_save_never_writes_through_a_link_to_the_campaign(fitted, tmp_path):
    campaign_path, result = fitted
    before = campaign_path.read_bytes()
    folder = tmp_path / "saved"
    folder.mkdir()
    os.symlink(campaign_path, folder / "result.json")
    for overwrite in (False, True):
        with pytest.raises(FileExistsError, match="result.json"):
            result.save(folder, overwrite=overwrite)
    assert campaign_path.read_bytes() == before
    assert os.path.islink(folder / "result.json")


def test_save_never_writes_through_a_dangling_link(fitted, tmp_path):
    _, result = fitted
    folder = tmp_path / "saved"
    folder.mkdir()
    outside = tmp_path / "elsewhere" / "history.csv"
    outside.parent.mkdir()
    os.symlink(outside, folder / "history.csv")
    for overwrite in (False, True):
        with pytest.raises(FileExistsError, match="history.csv"):
            result.save(folder, overwrite=overwrite)
    assert not outside.exists()


def test_save_never_replaces_a_users_own_file(fitted, tmp_path):
    _, result = fitted
    folder = tmp_path / "saved"
    folder.mkdir()
    (folder / "history.csv").write_text("my own notes\n")
    with pytest.raises(FileExistsError) as refused:
        result.save(folder)
    # The refusal does not suggest the flag that would not help.
    assert "not even with overwrite=True" in str(refused.value), refused.value
    with pytest.raises(FileExistsError, match="did not write"):
        result.save(folder, overwrite=True)
    assert (folder / "history.csv").read_text() == "my own notes\n"
    assert _listing(folder) == ["history.csv"]


def test_save_replaces_its_own_files_only_with_overwrite(fitted, tmp_path):
    _, result = fitted
    folder = result.save(tmp_path / "saved")
    assert rigfit.load_result(folder) == rigfit.load_result(folder)
    with pytest.raises(FileExistsError, match="overwrite=True"):
        result.save(folder)
    result.save(folder, overwrite=True)
    assert rigfit.load_result(folder).files["result.json"] == result.files["result.json"]


def test_a_save_that_fails_part_way_leaves_the_folder_as_it_was(fitted, tmp_path):
    _, result = fitted
    folder = result.save(tmp_path / "saved")
    before = {n: (tmp_path / "saved" / n).read_bytes() for n in _listing(folder)}
    # A file whose temporary sibling's name is too long for the file system
    # fails after the files before it were written: a full disk's stand-in.
    broken = rigfit.FitResult(result.files)
    broken.files = dict(result.files)
    broken.files["result.json"] = result.files["result.json"].replace(b"{", b"{ ", 1)
    broken.files["x" * 240 + ".csv"] = b"t\n"
    with pytest.raises(OSError) as failed:
        broken.save(folder, overwrite=True)
    assert not isinstance(failed.value, FileExistsError), failed.value
    after = {n: (tmp_path / "saved" / n).read_bytes() for n in _listing(folder)}
    # The manifest may name the file that was never written; nothing else
    # changed, and no temporary file is left.
    after.pop("rigfit-files.json"), before.pop("rigfit-files.json")
    assert after == before


def test_save_refuses_a_name_outside_the_folder(fitted, tmp_path):
    _, result = fitted
    forged = rigfit.FitResult(result.files)
    forged.files = dict(result.files, **{"../escaped.csv": b"t\n"})
    with pytest.raises(FileExistsError, match="outside"):
        forged.save(tmp_path / "saved")
    assert not (tmp_path / "escaped.csv").exists()


def test_no_temporary_job_folder_is_left_after_an_error_in_the_progress_callback(
        fitted, tmp_path, monkeypatch):
    campaign_path, _ = fitted
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))

    def progress(p):
        if p["stage"] == "ga" and p["generation"] == 1:
            raise ValueError("a bug in the notebook's callback")

    with pytest.raises(ValueError, match="callback"):
        rigfit.fit(rigfit.Campaign.from_json(campaign_path), backend="cpu", progress=progress)
    assert _listing(scratch) == []


def test_progress_true_without_tqdm_prints_a_plain_line(fitted, monkeypatch, capsys):
    campaign_path, _ = fitted
    for name in ("tqdm", "tqdm.auto"):
        monkeypatch.setitem(sys.modules, name, None)  # import fails
    rigfit.fit(rigfit.Campaign.from_json(campaign_path), backend="cpu", progress=True)
    err = capsys.readouterr().err
    assert "gen" in err and "best_r2=" in err, err


def test_a_campaign_at_a_path_that_is_not_utf8(fitted, tmp_path):
    campaign_path, _ = fitted
    folder = os.path.join(os.fsencode(tmp_path), b"camp\xff")
    os.mkdir(folder)
    for name in os.listdir(campaign_path.parent):
        if name.endswith((".json", ".csv")):
            shutil.copy(campaign_path.parent / name, os.path.join(os.fsdecode(folder), name))
    path = os.fsdecode(os.path.join(folder, b"bearing.json"))
    c = rigfit.Campaign.from_json(path)
    assert c.genes and "bearing" in repr(c) or c.name in repr(c)
    assert c.path == path


SIGINT_SCRIPT = """
import signal, sys, time, rigfit
signal.signal(signal.SIGINT, signal.default_int_handler)
c = rigfit.Campaign.from_json(sys.argv[1])
print("ready", flush=True)
t = time.monotonic()
try:
    rigfit.fit(c, backend="cpu")
    print("finished", time.monotonic() - t, flush=True)
except rigfit.Interrupted:
    print("interrupted", flush=True)
except KeyboardInterrupt:
    print("keyboard-interrupt", flush=True)  # landed in Python code after the job
except BaseException as e:
    print("OTHER", type(e).__name__, e, flush=True)
"""


def test_ctrl_c_as_the_job_ends_is_never_an_internal_error(fitted):
    """SIGINT sent at times spread over the end of a short job: the fit
    finishes, stops with Interrupted or a plain KeyboardInterrupt, and never
    reports a bug (rigfit once looked NumPy's C API up lazily, as the job's
    first array was made, and a Ctrl-C landing then failed the lookup)."""
    import signal
    import subprocess
    import time

    campaign_path, _ = fitted

    def run(delay):
        p = subprocess.Popen([sys.executable, "-c", SIGINT_SCRIPT, str(campaign_path)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        assert p.stdout.readline().startswith("ready")
        if delay is not None:
            time.sleep(delay)
            p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
        return out.strip(), err

    out, err = run(None)
    assert out.startswith("finished"), (out, err)
    took = float(out.split()[1])
    seen = []
    for i in range(12):
        out, err = run(took * (0.6 + 0.5 * i / 11))
        seen.append(out.split()[0] if out else "")
        assert out.split()[0] in ("finished", "interrupted", "keyboard-interrupt"), (out, err)
    print("outcomes:", seen)


def test_resume_as_the_interrupted_message_says_after_overrides(fitted):
    """The Interrupted message repeats the overrides the job was given, and
    following it word for word resumes the job."""
    campaign_path, _ = fitted
    campaign = rigfit.Campaign.from_json(campaign_path)

    def stop(p):
        if p["stage"] == "ga" and p["generation"] == 1:
            raise KeyboardInterrupt

    with pytest.raises(rigfit.Interrupted) as stopped:
        rigfit.fit(campaign, backend="cpu", population=24, generations=4, seed=5, progress=stop)
    call = str(stopped.value).split("continue with ", 1)[1]
    assert "population=24" in call and "generations=4" in call and "seed=5" in call, call
    try:
        resumed = eval(call, {"rigfit": rigfit, "campaign": campaign})
        fresh = rigfit.fit(campaign, backend="cpu", population=24, generations=4, seed=5)
        assert resumed.best_values == fresh.best_values
    finally:
        shutil.rmtree(stopped.value.checkpoint, ignore_errors=True)
