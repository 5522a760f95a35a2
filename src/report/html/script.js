// rigfit report: draws the figures from the data embedded in the page
// (#rigfit-data) as SVG, and zooms and pans the time figures. Plain
// JavaScript, no libraries, nothing fetched.
(function () {
  "use strict";
  var data = JSON.parse(document.getElementById("rigfit-data").textContent);
  var W = 900, M = { l: 78, r: 18, t: 30, b: 44 };
  var COLOURS = { measured: "#b4b9c0", model: "#1f5fa8", residual: "#3b3b3b" };
  var OTHERS = ["#d1793a", "#3a9a5b", "#8a5bb0", "#b8860b"];

  function fmt(v) {
    if (v === 0) return "0";
    var a = Math.abs(v);
    if (a >= 1e5 || a < 1e-3) {
      var s = v.toExponential(2).replace(/\.?0+e/, "e");
      var p = s.split("e");
      return p[0] + "e" + p[1].replace("+", "");
    }
    return String(parseFloat(v.toPrecision(4)));
  }
  function esc(s) {
    return String(s).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
  }
  function ticks(lo, hi, n) {
    var span = hi - lo;
    if (!(span > 0)) return [lo];
    var step = Math.pow(10, Math.floor(Math.log10(span / n)));
    var err = span / n / step;
    if (err >= 7.5) step *= 10; else if (err >= 3.5) step *= 5; else if (err >= 1.5) step *= 2;
    var out = [];
    for (var v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) {
      out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    }
    return out;
  }
  function logTicks(lo, hi) {
    var out = [], a = Math.floor(Math.log10(lo)), b = Math.ceil(Math.log10(hi));
    var every = Math.max(1, Math.ceil((b - a) / 6));
    for (var e = a; e <= b; e += every) {
      var v = Math.pow(10, e);
      if (v >= lo * 0.999 && v <= hi * 1.001) out.push(v);
    }
    return out;
  }

  // An axis frame: scales, grid, ticks and labels. opt: x0, x1, y0, y1,
  // ylog, xlabel, ylabel, height.
  function frame(opt) {
    // An empty or one-sample range still draws (no NaN coordinates).
    if (!(opt.x1 > opt.x0)) opt.x1 = opt.x0 + (opt.xlog ? opt.x0 : 1);
    if (!(opt.y1 > opt.y0)) opt.y1 = opt.y0 + (opt.ylog ? opt.y0 : 1);
    var H = opt.height, pw = W - M.l - M.r, ph = H - M.t - M.b;
    var ly = function (v) { return opt.ylog ? Math.log10(v) : v; };
    var lx = function (v) { return opt.xlog ? Math.log10(v) : v; };
    var Y0 = ly(opt.y0), Y1 = ly(opt.y1), X0 = lx(opt.x0), X1 = lx(opt.x1);
    var f = {
      H: H,
      x: function (v) { return M.l + (lx(v) - X0) / (X1 - X0) * pw; },
      y: function (v) { return M.t + ph - (ly(v) - Y0) / (Y1 - Y0) * ph; },
      parts: []
    };
    var g = ['<g class="grid">'];
    var lab = ['<g class="ticks">'];
    var xt = opt.xlog ? logTicks(opt.x0, opt.x1) : ticks(opt.x0, opt.x1, W < 600 ? 4 : 8);
    if (opt.xint) xt = xt.filter(function (v) { return v === Math.round(v); });
    xt.forEach(function (v) {
      var x = f.x(v).toFixed(1);
      g.push('<line x1="' + x + '" x2="' + x + '" y1="' + M.t + '" y2="' + (M.t + ph) + '"/>');
      lab.push('<text x="' + x + '" y="' + (M.t + ph + 16) + '" text-anchor="middle">' + fmt(v) + "</text>");
    });
    var yt = opt.ylog ? logTicks(opt.y0, opt.y1) : ticks(opt.y0, opt.y1, 5);
    yt.forEach(function (v) {
      var y = f.y(v).toFixed(1);
      g.push('<line x1="' + M.l + '" x2="' + (M.l + pw) + '" y1="' + y + '" y2="' + y + '"/>');
      lab.push('<text x="' + (M.l - 6) + '" y="' + (+y + 4) + '" text-anchor="end">' + fmt(v) + "</text>");
    });
    g.push("</g>");
    lab.push('<text class="label" x="' + (M.l + pw / 2) + '" y="' + (H - 6) + '" text-anchor="middle">' + esc(opt.xlabel) + "</text>");
    lab.push('<text class="label" transform="translate(16 ' + (M.t + ph / 2) + ') rotate(-90)" text-anchor="middle">' + esc(opt.ylabel) + "</text>");
    lab.push("</g>");
    f.grid = g.join("");
    f.labels = lab.join("") + '<rect class="box" x="' + M.l + '" y="' + M.t + '" width="' + pw + '" height="' + ph + '" fill="none"/>';
    f.clip = '<clipPath id="CLIP"><rect x="' + M.l + '" y="' + M.t + '" width="' + pw + '" height="' + ph + '"/></clipPath>';
    return f;
  }

  // A polyline path of the points of (xs, ys) inside [x0, x1] (one beyond
  // each end), broken at nulls.
  function path(f, xs, ys, x0, x1, ylog) {
    var d = [], pen = false, n = xs.length;
    for (var k = 0; k < n; k++) {
      if (xs[k] < x0 && !(k + 1 < n && xs[k + 1] >= x0)) continue;
      if (xs[k] > x1 && !(k > 0 && xs[k - 1] <= x1)) break;
      var v = ys[k];
      if (v === null || (ylog && !(v > 0))) { pen = false; continue; }
      d.push((pen ? "L" : "M") + f.x(xs[k]).toFixed(1) + " " + f.y(v).toFixed(1));
      pen = true;
    }
    return d.join("");
  }
  function extent(list, x0, x1, ylog) {
    var lo = Infinity, hi = -Infinity;
    list.forEach(function (s) {
      for (var k = 0; k < s.x.length; k++) {
        var v = s.y[k];
        if (s.x[k] < x0 || s.x[k] > x1 || v === null || (ylog && !(v > 0))) continue;
        if (v < lo) lo = v;
        if (v > hi) hi = v;
      }
    });
    if (!(lo <= hi)) return ylog ? [1e-6, 1] : [-1, 1];
    if (ylog) return [lo / 1.5, hi * 1.5];
    var pad = (hi - lo) * 0.06 || Math.abs(hi) * 0.1 || 1;
    return [lo - pad, hi + pad];
  }
  function legend(items) {
    var x = M.l, out = ['<g class="legend">'];
    items.forEach(function (it) {
      out.push('<line x1="' + x + '" x2="' + (x + 18) + '" y1="14" y2="14" stroke="' + it.colour + '" stroke-width="2.5"' +
        (it.dash ? ' stroke-dasharray="5 3"' : "") + "/>");
      out.push('<text x="' + (x + 23) + '" y="18">' + esc(it.label) + "</text>");
      x += 36 + 6.6 * it.label.length;
    });
    out.push("</g>");
    return out.join("");
  }
  function put(svg, f, body, id) {
    svg.innerHTML = f.clip.replace("CLIP", id) + f.grid + '<g clip-path="url(#' + id + ')">' + body + "</g>" + f.labels + (f.extra || "");
  }
  var uid = 0;

  // ---- time figures ------------------------------------------------------
  function timeFigure(fig, range) {
    var exp = data[fig.dataset.from][+fig.dataset.index];
    var kind = fig.dataset.kind, svg = fig.querySelector("svg");
    var series = kind === "fit" ? exp.fit : (exp.residual ? [exp.residual] : []);
    var t0 = range[0], t1 = range[1];
    var ys = extent(series, t0, t1, false);
    var f = frame({ x0: t0, x1: t1, y0: ys[0], y1: ys[1], height: 300, xlabel: "record time (s)",
      ylabel: (kind === "fit" ? exp.quantity : "residual") + " (" + exp.unit + ")" });
    var body = [];
    exp.window.forEach(function (s) {
      var a = Math.max(s[0], t0), b = Math.min(s[1], t1);
      if (b > a) body.push('<rect class="win" x="' + f.x(a).toFixed(1) + '" y="' + M.t + '" width="' + (f.x(b) - f.x(a)).toFixed(1) + '" height="' + (300 - M.t - M.b) + '"/>');
    });
    if (kind === "residual") body.push('<line class="zero" x1="' + M.l + '" x2="' + (W - M.r) + '" y1="' + f.y(0).toFixed(1) + '" y2="' + f.y(0).toFixed(1) + '"/>');
    var items = [], other = 0;
    series.forEach(function (s) {
      var c = COLOURS[s.role] || OTHERS[other++ % OTHERS.length];
      var w = s.role === "measured" ? 2.4 : 1.5;
      body.push('<path d="' + path(f, s.x, s.y, t0, t1, false) + '" fill="none" stroke="' + c + '" stroke-width="' + w + '" stroke-linejoin="round"/>');
      items.push({ label: s.label, colour: c });
    });
    f.extra = legend(items);
    put(svg, f, body.join(""), "c" + (uid++));
  }

  var groups = {};
  function group(fig) {
    var key = fig.dataset.from + ":" + fig.dataset.index;
    if (!groups[key]) {
      groups[key] = { figs: [], a0: fig.dataset.t0, a1: fig.dataset.t1 };
      groups[key].full = [parseFloat(groups[key].a0), parseFloat(groups[key].a1)];
      groups[key].range = groups[key].full.slice();
    }
    return groups[key];
  }
  function show(g) {
    var full = g.range[0] === g.full[0] && g.range[1] === g.full[1];
    g.figs.forEach(function (fig) {
      fig.dataset.t0 = full ? g.a0 : String(g.range[0]);
      fig.dataset.t1 = full ? g.a1 : String(g.range[1]);
      timeFigure(fig, g.range);
    });
  }
  function setRange(g, a, b) {
    var width = b - a, fw = g.full[1] - g.full[0];
    if (!(width > 0)) return;
    if (width >= fw) { g.range = g.full.slice(); show(g); return; }
    width = Math.max(width, fw * 1e-6);
    if (a < g.full[0]) a = g.full[0];
    if (a + width > g.full[1]) a = g.full[1] - width;
    g.range = [a, a + width];
    show(g);
  }
  function plotX(svg, clientX) {
    var r = svg.getBoundingClientRect();
    var x = (clientX - r.left) * W / r.width;
    return Math.min(1, Math.max(0, (x - M.l) / (W - M.l - M.r)));
  }
  document.querySelectorAll("figure.time").forEach(function (fig) {
    var g = group(fig), svg = fig.querySelector("svg");
    g.figs.push(fig);
    svg.addEventListener("wheel", function (e) {
      e.preventDefault();
      var k = Math.pow(1.0015, Math.max(-1000, Math.min(1000, e.deltaY)));
      var w = g.range[1] - g.range[0], at = g.range[0] + plotX(svg, e.clientX) * w;
      setRange(g, at - (at - g.range[0]) * k, at + (g.range[1] - at) * k);
    }, { passive: false });
    var drag = null;
    svg.addEventListener("pointerdown", function (e) {
      drag = { x: e.clientX, range: g.range.slice(), width: svg.getBoundingClientRect().width };
      svg.setPointerCapture(e.pointerId);
    });
    svg.addEventListener("pointermove", function (e) {
      if (!drag) return;
      var w = drag.range[1] - drag.range[0];
      var dt = (e.clientX - drag.x) * W / drag.width / (W - M.l - M.r) * w;
      setRange(g, drag.range[0] - dt, drag.range[1] - dt);
    });
    var end = function () { drag = null; };
    svg.addEventListener("pointerup", end);
    svg.addEventListener("pointercancel", end);
    fig.querySelectorAll("button[data-zoom]").forEach(function (b) {
      b.addEventListener("click", function () {
        var z = b.dataset.zoom, c = (g.range[0] + g.range[1]) / 2, h = (g.range[1] - g.range[0]) / 2;
        if (z === "reset") { g.range = g.full.slice(); show(g); }
        else if (z === "in") setRange(g, c - h / 2, c + h / 2);
        else setRange(g, c - 2 * h, c + 2 * h);
      });
    });
  });
  Object.keys(groups).forEach(function (k) { show(groups[k]); });

  // ---- spectra ------------------------------------------------------------
  document.querySelectorAll("figure.spectrum").forEach(function (fig) {
    var exp = data[fig.dataset.from][+fig.dataset.index];
    var s = exp.spectrum, svg = fig.querySelector("svg");
    // A log frequency axis from the first bin above 0 Hz to Nyquist.
    var xs = s.x.slice(1), vs = s.y.slice(1);
    var x0 = xs.length ? xs[0] : 1, x1 = xs.length > 1 ? xs[xs.length - 1] : 10;
    var ys = extent([{ x: xs, y: vs }], x0, x1, true);
    var f = frame({ x0: x0, x1: x1, xlog: true, y0: ys[0], y1: ys[1], ylog: true, height: 260, xlabel: "frequency (Hz)", ylabel: "amplitude (" + exp.unit + ")" });
    var body = ['<path d="' + path(f, xs, vs, x0, x1, true) + '" fill="none" stroke="#1f5fa8" stroke-width="1.2"/>'];
    var items = [{ label: "residual amplitude", colour: "#1f5fa8" }];
    var shown = exp.modes.filter(function (m) { return m !== null && m >= x0 && m <= x1; });
    shown.forEach(function (m) {
      var x = f.x(m).toFixed(1);
      body.push('<line class="mode" x1="' + x + '" x2="' + x + '" y1="' + M.t + '" y2="' + (260 - M.b) + '"><title>natural frequency ' + fmt(m) + ' Hz</title></line>');
    });
    if (shown.length) items.push({ label: "natural frequencies", colour: "#b2182b", dash: true });
    if (!s.x.length) body.push('<text x="' + W / 2 + '" y="130" text-anchor="middle">too few samples in the fit window for a spectrum</text>');
    f.extra = legend(items);
    put(svg, f, body.join(""), "c" + (uid++));
  });

  // ---- convergence ----------------------------------------------------------
  document.querySelectorAll("figure.convergence").forEach(function (fig) {
    var c = data.convergence, svg = fig.querySelector("svg");
    var g = c.generation, x1 = Math.max(1, g[g.length - 1] || 1);
    var best = { x: g, y: c.best }, median = { x: g, y: c.median };
    var list = [best, median];
    if (c.floor) list.push({ x: [0], y: [c.floor] });
    var ys = extent(list, -Infinity, Infinity, true);
    var f = frame({ x0: g[0] || 0, x1: x1, y0: ys[0], y1: ys[1], ylog: true, xint: true, height: 280, xlabel: "generation", ylabel: "cost (1 − R²)" });
    var body = ['<path d="' + path(f, g, c.median, -Infinity, Infinity, true) + '" fill="none" stroke="#d1793a" stroke-width="1.6"/>',
      '<path d="' + path(f, g, c.best, -Infinity, Infinity, true) + '" fill="none" stroke="#1f5fa8" stroke-width="2"/>'];
    var items = [{ label: "best", colour: "#1f5fa8" }, { label: "median", colour: "#d1793a" }];
    if (c.floor) {
      var y = f.y(c.floor).toFixed(1);
      body.push('<line class="floor" x1="' + M.l + '" x2="' + (W - M.r) + '" y1="' + y + '" y2="' + y + '"/>');
      items.push({ label: "noise floor", colour: "#b2182b", dash: true });
    }
    f.extra = legend(items);
    put(svg, f, body.join(""), "c" + (uid++));
  });

  // ---- profiles -------------------------------------------------------------
  document.querySelectorAll("figure.profile").forEach(function (fig) {
    var p = data.profiles[+fig.dataset.index], svg = fig.querySelector("svg");
    var list = [p];
    if (p.threshold !== null && p.x.length) list.push({ x: [p.x[0]], y: [p.threshold] });
    if (!p.x.length) p = { name: p.name, ylabel: p.ylabel, x: [0, 1], y: [null, null], threshold: p.threshold, value: null };
    var x0 = Math.min.apply(null, p.x), x1 = Math.max.apply(null, p.x);
    if (!(x1 > x0)) { x0 = (x0 || 1) * 0.9; x1 = (x1 || 1) * 1.1; }
    var ys = extent(list, -Infinity, Infinity, false);
    // The part that decides the interval: the held values up to ten times
    // the threshold, and one beyond on each side (the rest is clipped; the
    // caption says so, and result.json has every point).
    var q = p.threshold, near = [];
    if (q !== null && q > 0) {
      p.x.forEach(function (x, k) { if (p.y[k] !== null && p.y[k] <= 10 * q) near.push(k); });
    }
    if (near.length > 1) {
      var a = Math.max(0, near[0] - 1), b = Math.min(p.x.length - 1, near[near.length - 1] + 1);
      if (p.x[b] > p.x[a]) { x0 = p.x[a]; x1 = p.x[b]; }
      var top = Math.min(ys[1], 10 * q);
      ys = [-0.05 * top, top];
    }
    var saved = W; W = 420;
    var f = frame({ x0: x0, x1: x1, y0: ys[0], y1: ys[1], height: 240, xlabel: p.name, ylabel: p.ylabel });
    var body = ['<path d="' + path(f, p.x, p.y, -Infinity, Infinity, false) + '" fill="none" stroke="#1f5fa8" stroke-width="1.8"/>'];
    p.x.forEach(function (x, k) {
      if (p.y[k] !== null) body.push('<circle cx="' + f.x(x).toFixed(1) + '" cy="' + f.y(p.y[k]).toFixed(1) + '" r="2.5" fill="#1f5fa8"/>');
    });
    if (p.threshold !== null) {
      var y = f.y(p.threshold).toFixed(1);
      body.push('<line class="floor" x1="' + M.l + '" x2="' + (W - M.r) + '" y1="' + y + '" y2="' + y + '"/>');
    }
    if (p.value !== null && p.value >= x0 && p.value <= x1) {
      var xv = f.x(p.value).toFixed(1);
      body.push('<line class="fitted" x1="' + xv + '" x2="' + xv + '" y1="' + M.t + '" y2="' + (240 - M.b) + '"/>');
    }
    put(svg, f, body.join(""), "c" + (uid++));
    W = saved;
  });
})();
