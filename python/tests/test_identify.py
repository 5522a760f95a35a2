"""The pre-calibration and identification methods on arrays give the numbers
the CLI's --json prints for the same record."""

import json

import numpy as np
import pytest

import rigfit
from conftest import CAMPAIGNS


def _two_columns(path):
    rows = [r for r in path.read_text().splitlines() if r.strip() and not r.startswith("#")]
    table = np.loadtxt(rows[1:], delimiter=",", ndmin=2)
    return table[:, 0], table[:, 1]


def test_ringdown_matches_the_cli(cli):
    path = CAMPAIGNS / "ringdown_synthetic.csv"
    t, f = _two_columns(path)
    r = rigfit.ringdown(t, f, m1=7.9)
    want = json.loads(cli("--json", "ringdown", path, "--m1", "7.9").stdout)
    assert r["ringdown"] == want["ringdown"]
    assert r.fragment == want["fragment"]
    assert r["ringdown"]["natural_frequency_hz"] > 0


def test_fit_specimen_matches_the_cli(cli):
    path = CAMPAIGNS / "specimen_quasistatic_synthetic.csv"
    e, f = _two_columns(path)
    r = rigfit.fit_specimen(e, f, degree=3)
    want = json.loads(cli("--json", "fit-specimen", path, "--degree", "3").stdout)
    assert r["fit"] == want["fit"]
    assert r.fragment == want["fragment"]


def test_a_too_short_record_is_a_data_error():

    with pytest.raises(rigfit.DataError):
        rigfit.ringdown([0.0, 1.0], [1.0, 0.0])


def test_frf_matches_the_cli(cli, tmp_path):
    from scipy import signal
    m, k, zeta = 2.0, 8000.0, 0.05
    c = 2 * zeta * np.sqrt(k * m)
    t = np.arange(8192) / 100.0
    u = np.random.default_rng(3).normal(0.0, 10.0, t.size)
    _, y, _ = signal.lsim(signal.lti([1.0], [m, c, k]), u, t)
    path = tmp_path / "rec.csv"
    rows = zip(t.tolist(), u.tolist(), y.tolist())
    path.write_text("t_s,u_N,x_m\n" + "".join(f"{a!r},{b!r},{d!r}\n" for a, b, d in rows))
    r = rigfit.frf(t, u, y, f_min=3.0, f_max=28.0)
    want = json.loads(cli("--json", "identify", "frf", path, "--f-min", "3", "--f-max", "28").stdout)
    assert r["modal"] == want["modal"] and r["welch"] == want["welch"]
    assert r.fragment == want["fragment"]
    mode = r["modal"]["modes"][0]
    assert abs(mode["natural_frequency_hz"] - np.sqrt(k / m) / (2 * np.pi)) < 0.05
    assert r.spectra["h1"].dtype == complex and len(r.spectra["freqs"]) == len(r.spectra["coherence"])


def test_rfs_matches_the_cli(cli, tmp_path):
    from scipy.integrate import solve_ivp
    m, k, c, k3 = 2.0, 8000.0, 6.0, 4e8
    fs = 2000.0
    t = np.arange(8000) / fs

    def rhs(_, s):
        x, v = s
        return [v, -(k * x + k3 * x**3 + c * v) / m]

    sol = solve_ivp(rhs, (0, t[-1]), [0.01, 0.0], t_eval=t, rtol=1e-10, atol=1e-12)
    x, v = sol.y
    a = np.zeros_like(t)        # the base's acceleration: a free decay, the base still
    path = tmp_path / "free.csv"
    rows = zip(t.tolist(), x.tolist(), a.tolist())
    path.write_text("t_s,x_m,a_m_s2\n" + "".join(f"{p!r},{q!r},{r!r}\n" for p, q, r in rows))
    r = rigfit.rfs(t, x, a, mass=m, terms=("linear", "cubic", "viscous"))
    want = json.loads(cli("--json", "identify", "rfs", path, "--mass", "2",
                          "--terms", "linear,cubic,viscous").stdout)
    assert r["dpe"] == want["dpe"]
    assert r.fragment == want["fragment"]
    fitted = {c["param"]: c["value"] for c in r["dpe"]["coefficients"]}
    assert abs(fitted["kf1"] / k - 1) < 0.01 and abs(fitted["cf1"] / c - 1) < 0.01, fitted


def test_idim_on_the_emps_record_matches_the_cli(cli):
    path = CAMPAIGNS.parent / "tests" / "data" / "emps" / "emps_position_voltage.csv"
    q, v = _two_columns(path)
    gain = 35.15065188248547
    r = rigfit.idim(q, v, sample_rate=1000.0, gain=gain)
    want = json.loads(cli("--json", "identify", "idim", path, "--position", "position_m",
                          "--force", "controller_voltage_V", "--gain", repr(gain),
                          "--sample-rate", "1000").stdout)
    assert r["idim"] == want["idim"]
    assert r.fragment == want["fragment"]
    with pytest.raises(rigfit.CampaignError, match="sample_rate"):
        rigfit.idim(q, v)


def test_nimiso_matches_the_cli(cli, tmp_path):
    # A Duffing oscillator under a random force, integrated by RK4 with the
    # force held over each sample interval.
    m, c, k, k3, fs = 1.0, 4.0, 4.0e4, 2.0e9, 1000.0
    n, sub = 16384, 4
    force = np.random.default_rng(7).normal(0.0, 20.0, n)
    h = 1.0 / fs / sub
    x = np.zeros(n)
    s = np.zeros(2)
    for i in range(n - 1):
        for _ in range(sub):
            def d(y, F=force[i]):
                return np.array([y[1], (F - c * y[1] - k * y[0] - k3 * y[0] ** 3) / m])
            k1 = d(s)
            k2 = d(s + h / 2 * k1)
            k3_ = d(s + h / 2 * k2)
            k4 = d(s + h * k3_)
            s = s + h / 6 * (k1 + 2 * k2 + 2 * k3_ + k4)
        x[i + 1] = s[0]
    t = np.arange(n) / fs
    path = tmp_path / "duffing.csv"
    rows = zip(t.tolist(), x.tolist(), force.tolist())
    path.write_text("t_s,x_m,f_N\n" + "".join(f"{p!r},{q!r},{r!r}\n" for p, q, r in rows))
    r = rigfit.nimiso(t, x, force, f_min=5.0, f_max=100.0)
    want = json.loads(cli("--json", "identify", "nimiso", path, "--f-min", "5",
                          "--f-max", "100").stdout)
    assert r["nimiso"] == want["nimiso"]
    assert r.fragment == want["fragment"]


def _write(path, header, columns):
    rows = zip(*(np.asarray(c).tolist() for c in columns))
    path.write_text(header + "\n" + "".join(",".join(repr(v) for v in r) + "\n" for r in rows))


def test_arx_matches_the_cli(cli, tmp_path):
    # A mass on a spring and a damper from a randomly moving base: the
    # transmissibility of the accelerations is (c s + k) / (m s² + c s + k).
    from scipy import signal
    m, k, c, fs = 2.0, 8000.0, 20.0, 200.0
    t = np.arange(16384) / fs
    u = np.random.default_rng(5).normal(0.0, 1.0, t.size)
    _, y, _ = signal.lsim(signal.lti([c, k], [m, c, k]), u, t)
    path = tmp_path / "arx.csv"
    _write(path, "t_s,base_m_s2,mass_m_s2", (t, u, y))
    r = rigfit.arx(t, u, y, mass=m, f_min=1.0, f_max=40.0)
    want = json.loads(cli("--json", "identify", "arx", path, "--mass", "2", "--f-min", "1",
                          "--f-max", "40").stdout)
    assert r["element"] == want["element"] and r["arx"] == want["arx"]
    assert r["welch"] == want["welch"]
    assert r.fragment == want["fragment"]
    assert abs(r["element"]["stiffness"] / k - 1) < 0.05, r["element"]
    assert r.spectra["t"].shape == r.spectra["coherence"].shape == (1, len(r.spectra["freqs"]))
    with pytest.raises(rigfit.CampaignError, match="one positive mass"):
        rigfit.arx(t, u, y, mass=[m, m], f_min=1.0, f_max=40.0)


def test_impedance_matches_the_cli(cli, tmp_path):
    # A point mass on a 2 × 2 spring and damper, struck in x and then in y.
    from scipy import signal
    mass, fs, n = 10.0, 4096.0, 1024
    K = np.array([[4e6, 1e6], [1e6, 5e6]])
    C = np.array([[400.0, 0.0], [0.0, 500.0]])
    a = np.block([[np.zeros((2, 2)), np.eye(2)], [-K / mass, -C / mass]])
    b = np.vstack([np.zeros((2, 2)), np.eye(2) / mass])
    sys = signal.StateSpace(a, b, np.hstack([np.eye(2), np.zeros((2, 2))]), np.zeros((2, 2)))
    t = np.arange(n) / fs
    pulse = np.where((t >= 0.01) & (t <= 0.014), 500.0 * np.sin(np.pi * (t - 0.01) / 0.004), 0.0)
    impacts = []
    for axis in (0, 1):
        force = np.zeros((n, 2))
        force[:, axis] = pulse
        _, d, _ = signal.lsim(sys, force, t)
        impacts.append((pulse, d[:, 0], d[:, 1]))
    paths = [tmp_path / "hx.csv", tmp_path / "hy.csv"]
    for p, (f, x, y) in zip(paths, impacts):
        _write(p, "t_s,force_N,x_m,y_m", (t, f, x, y))
    r = rigfit.impedance(t, impacts[0], impacts[1], f_min=20.0, f_max=300.0)
    want = json.loads(cli("--json", "identify", "impedance", *paths, "--f-min", "20",
                          "--f-max", "300").stdout)
    assert r["impedance"] == want["impedance"]
    assert r.fragment == want["fragment"]
    fitted = r["impedance"]["stiffness"]
    assert abs(fitted[0][0] / K[0, 0] - 1) < 0.1, fitted
    with pytest.raises(rigfit.CampaignError, match="x_impact"):
        rigfit.impedance(t, impacts[0][:2], impacts[1], f_min=20.0, f_max=300.0)


def test_sensitivity_matches_the_cli(cli, tmp_path):
    # A quarter car on a randomly moving wheel pan (displacements), its strut
    # softened by 3 %.
    from scipy import signal
    m1, m2, k1, k2, c2, fs = 40.0, 350.0, 2e5, 3e4, 1500.0, 200.0
    t = np.arange(2 ** 15) / fs
    xb = np.random.default_rng(11).normal(0.0, 1e-3, t.size)
    records = []
    for k in (k2, 0.97 * k2):
        a = np.array([[0, 0, 1, 0], [0, 0, 0, 1],
                      [-(k1 + k) / m1, k / m1, -c2 / m1, c2 / m1],
                      [k / m2, -k / m2, c2 / m2, -c2 / m2]])
        b = np.array([[0.0], [0.0], [k1 / m1], [0.0]])
        sys = signal.StateSpace(a, b, np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]]), np.zeros((2, 1)))
        _, d, _ = signal.lsim(sys, xb, t)
        records.append((xb, d[:, 0], d[:, 1]))
    paths = [tmp_path / "base.csv", tmp_path / "changed.csv"]
    for p, (w, u, s) in zip(paths, records):
        _write(p, "t_s,wheel_pan_m,unsprung_m,sprung_m", (t, w, u, s))
    r = rigfit.sensitivity(t, records[0], records[1], k1=k1, f_min=5.0, f_max=15.0,
                           segment=4096, base_value=k2)
    want = json.loads(cli("--json", "identify", "sensitivity", *paths, "--k1", "200000",
                          "--f-min", "5", "--f-max", "15", "--segment", "4096",
                          "--base-value", "30000").stdout)
    assert r["sensitivity"] == want["sensitivity"] and r["welch"] == want["welch"]
    assert r.fragment == want["fragment"]
    assert abs(r["sensitivity"]["change"]["mean"] / (-0.03 * k2) - 1) < 0.1, r["sensitivity"]
    assert abs(r.fragment["params"]["k2"]["init"] / (0.97 * k2) - 1) < 0.01
