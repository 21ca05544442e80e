/* hnc_cam HTML report: backplot on a canvas, program text, step-through.
   Data: the JSON in <script id="hnc-data">; coordinates in micrometres, X as radius.
   No network access, no library: the canvas draws lines and true arcs. */
(function () {
  "use strict";
  var D = JSON.parse(document.getElementById("hnc-data").textContent);
  var M = D.moves;
  var N = M.k.length;
  var U = 1000.0; // um per mm
  var KIND = ["rapid", "line", "arc", "thread", "dwell"];
  var COLOURS = ["#2ca02c", "#1f77b4", "#8c564b", "#17becf", "#bcbd22", "#7f7f7f", "#e377c2",
                 "#006d5b", "#393b79"];

  // ---- rings: delta-encoded integer um -> absolute um; frames may refer to earlier ones ----
  function undelta(rings) {
    if (!rings) return [];
    return rings.map(function (r) {
      var out = new Array(r.length), z = 0, x = 0;
      for (var k = 0; k < r.length; k += 2) { z += r[k]; x += r[k + 1]; out[k] = z; out[k + 1] = x; }
      return out;
    });
  }
  (function () {
    var K = D.keyframes, k;
    for (k = 0; k < K.length; k++) if (typeof K[k].rings !== "number") K[k].rings = undelta(K[k].rings);
    for (k = 0; k < K.length; k++) if (typeof K[k].rings === "number") K[k].rings = K[K[k].rings].rings;
    D.stock = undelta(D.stock);
    if (D.chuck) D.chuck = undelta(D.chuck);
    var F = D.findings;
    F.overcut = undelta(F.overcut); F.undercut = undelta(F.undercut);
    F.unreachable_region = undelta(F.unreachable_region);
  })();

  // ---- moves: start/end (mm), arcs, line index ------------------------------------------
  var z0 = new Float64Array(N), x0 = new Float64Array(N), z1 = new Float64Array(N),
      x1 = new Float64Array(N);
  var arcC = {}; // move index -> [cz, cx, cw]
  var i, j;
  var starts = {};
  for (i = 0; i < M.s.length; i += 3) starts[M.s[i]] = [M.s[i + 1], M.s[i + 2]];
  for (i = 0; i < M.a.length; i += 4) arcC[M.a[i]] = [M.a[i + 1] / U, M.a[i + 2] / U, M.a[i + 3]];
  var pz = M.x0z0[0], px = M.x0z0[1];
  for (i = 0; i < N; i++) {
    if (starts[i]) { pz = starts[i][0]; px = starts[i][1]; }
    z0[i] = pz / U; x0[i] = px / U;
    pz = M.e[2 * i]; px = M.e[2 * i + 1];
    z1[i] = pz / U; x1[i] = px / U;
  }
  var byLine = {};
  for (i = 0; i < N; i++) {
    var ln = M.l[i];
    (byLine[ln] || (byLine[ln] = [])).push(i);
  }
  var opColour = M.ops.map(function (name, k) { return name === "rapid" ? "#d62728" : null; });
  var c = 0;
  for (i = 0; i < opColour.length; i++) if (!opColour[i]) opColour[i] = COLOURS[c++ % COLOURS.length];

  // ---- state ----------------------------------------------------------------------------
  var state = {
    step: N, // moves done
    frame: D.keyframes.length - 1,
    selected: [], // move indices
    selectedLine: 0,
    hover: -1,
    hoverLine: 0,
    drawn: 0,
    layers: {stock: true, material: true, model: true, path: true, rapid: true, findings: true},
    playing: false
  };

  // ---- view -----------------------------------------------------------------------------
  var cv = document.getElementById("plot");
  var ctx = cv.getContext("2d");
  var view = {s: 1, cz: 0, cx: 0};
  function bounds() {
    var b = D.view; // [zmin, xmin, zmax, xmax] mm
    return b;
  }
  function fit() {
    var b = bounds();
    var w = cv.clientWidth || 800, h = cv.clientHeight || 500;
    var dz = Math.max(b[2] - b[0], 1e-3), dx = Math.max(b[3] - b[1], 1e-3);
    view.s = 0.9 * Math.min(w / dz, h / dx);
    view.cz = (b[0] + b[2]) / 2;
    view.cx = (b[1] + b[3]) / 2;
    redraw();
  }
  function sx(z) { return (z - view.cz) * view.s + cv.width / dpr() / 2; }
  function sy(x) { return cv.height / dpr() / 2 - (x - view.cx) * view.s; }
  function wz(px) { return (px - cv.width / dpr() / 2) / view.s + view.cz; }
  function wx(py) { return (cv.height / dpr() / 2 - py) / view.s + view.cx; }
  function dpr() { return window.devicePixelRatio || 1; }
  function resize() {
    var r = dpr();
    cv.width = Math.max(1, Math.round(cv.clientWidth * r));
    cv.height = Math.max(1, Math.round(cv.clientHeight * r));
    redraw();
  }

  // ---- drawing --------------------------------------------------------------------------
  function ringPath(flat) {
    if (flat.length < 4) return;
    ctx.moveTo(sx(flat[0] / U), sy(flat[1] / U));
    for (var k = 2; k < flat.length; k += 2) ctx.lineTo(sx(flat[k] / U), sy(flat[k + 1] / U));
    ctx.closePath();
  }
  function fillRings(rings, fill, stroke, lw) {
    if (!rings || !rings.length) return;
    ctx.beginPath();
    for (var k = 0; k < rings.length; k++) ringPath(rings[k]);
    if (fill) { ctx.fillStyle = fill; ctx.fill("evenodd"); }
    if (stroke) { ctx.strokeStyle = stroke; ctx.lineWidth = lw || 1; ctx.stroke(); }
  }
  function arcTo(cz, cx, zs, xs, ze, xe, cw) {
    // world angle atan2(x - xc, z - zc); the screen flips y, so a cw arc (G02, angle
    // decreasing) runs with the canvas's clockwise sense
    var r = Math.hypot(xs - cx, zs - cz);
    var a0 = -Math.atan2(xs - cx, zs - cz), a1 = -Math.atan2(xe - cx, ze - cz);
    if (Math.abs(a1 - a0) < 1e-12) a1 = a0 + (cw ? 2 * Math.PI : -2 * Math.PI);
    ctx.arc(sx(cz), sy(cx), r * view.s, a0, a1, !cw);
  }
  function moveSeg(k) {
    ctx.moveTo(sx(z0[k]), sy(x0[k]));
    if (M.k[k] === 2 && arcC[k]) {
      var a = arcC[k];
      arcTo(a[0], a[1], z0[k], x0[k], z1[k], x1[k], a[2] === 1);
    } else if (M.k[k] === 4) {
      ctx.moveTo(sx(z1[k]) + 2.5, sy(x1[k]));
      ctx.arc(sx(z1[k]), sy(x1[k]), 2.5, 0, 2 * Math.PI);
    } else {
      ctx.lineTo(sx(z1[k]), sy(x1[k]));
    }
  }
  function segsOf(list) {
    ctx.beginPath();
    for (var k = 0; k < list.length; k++) moveSeg(list[k]);
  }
  function drawModel() {
    var segs = D.model || [];
    ctx.beginPath();
    for (var k = 0; k < segs.length; k++) {
      var s = segs[k];
      ctx.moveTo(sx(s[0] / U), sy(s[1] / U));
      if (s.length > 4) arcTo(s[4] / U, s[5] / U, s[0] / U, s[1] / U, s[2] / U, s[3] / U, s[6] === 1);
      else ctx.lineTo(sx(s[2] / U), sy(s[3] / U));
    }
    ctx.strokeStyle = "#000"; ctx.lineWidth = 1.4; ctx.setLineDash([]); ctx.stroke();
  }
  /* Workholding: the chuck jaws, when the data carries them (D.chuck = list of rings in the
     same units); nothing is drawn while the simulator does not model them. */
  function drawChuck(chuck) {
    if (!chuck || !chuck.length) return;
    fillRings(chuck, "rgba(90,90,90,0.55)", "#333", 1);
  }
  function drawPath() {
    var done = state.step, drawn = 0;
    // group by operation and by done/not done, one path each
    var groups = {};
    for (var k = 0; k < N; k++) {
      if (M.k[k] === 0 && !state.layers.rapid) continue;
      var key = M.g[k] + (k < done ? "d" : "f");
      (groups[key] || (groups[key] = [])).push(k);
      drawn++;
    }
    for (var key2 in groups) {
      var g = parseInt(key2, 10), future = key2.charAt(key2.length - 1) === "f";
      var list = groups[key2];
      segsOf(list);
      var rapid = M.ops[g] === "rapid";
      ctx.setLineDash(rapid ? [5, 4] : []);
      ctx.globalAlpha = future ? 0.18 : (rapid ? 0.75 : 1.0);
      ctx.strokeStyle = opColour[g];
      ctx.lineWidth = rapid ? 0.8 : 1.1;
      ctx.stroke();
    }
    ctx.globalAlpha = 1; ctx.setLineDash([]);
    state.drawn = drawn;
  }
  function drawHighlight(list, colour, width) {
    if (!list.length) return;
    segsOf(list);
    ctx.setLineDash([]); ctx.strokeStyle = colour; ctx.lineWidth = width; ctx.stroke();
  }
  function mark(z, x, colour, label, shape) {
    var X = sx(z), Y = sy(x);
    ctx.beginPath();
    if (shape === "diamond") { ctx.moveTo(X, Y - 6); ctx.lineTo(X + 6, Y); ctx.lineTo(X, Y + 6); ctx.lineTo(X - 6, Y); ctx.closePath(); }
    else if (shape === "x") { ctx.moveTo(X - 6, Y - 6); ctx.lineTo(X + 6, Y + 6); ctx.moveTo(X + 6, Y - 6); ctx.lineTo(X - 6, Y + 6); }
    else ctx.arc(X, Y, 7, 0, 2 * Math.PI);
    ctx.strokeStyle = colour; ctx.lineWidth = 2; ctx.stroke();
    if (label) {
      ctx.font = "12px sans-serif"; ctx.fillStyle = colour;
      ctx.fillText(label, X + 9, Y - 8);
    }
  }
  function drawFindings() {
    var F = D.findings;
    var b = D.view;
    for (var k = 0; k < F.threads.length; k++) {
      var t = F.threads[k];
      var za = sx(t.z0 / U), zb = sx(t.z1 / U);
      ctx.fillStyle = t.ok === false ? "rgba(214,39,40,0.10)" : "rgba(44,160,44,0.10)";
      ctx.fillRect(Math.min(za, zb), 0, Math.abs(zb - za), cv.height);
      ctx.fillStyle = t.ok === false ? "#d62728" : "#2ca02c";
      ctx.font = "11px sans-serif";
      ctx.fillText("thread" + (t.ok === null ? "" : (t.ok ? " ok" : " FAIL")), Math.min(za, zb) + 3, 14);
    }
    fillRings(F.overcut, "rgba(214,39,40,0.6)", "#d62728", 1.5);
    fillRings(F.undercut, "rgba(255,127,14,0.6)", "#ff7f0e", 1.5);
    fillRings(F.unreachable_region, "rgba(148,103,189,0.35)", "#9467bd", 1);
    for (k = 0; k < F.marks.length; k++) {
      var m = F.marks[k];
      var col = m.kind === "overcut" ? "#d62728" : (m.kind === "undercut" ? "#ff7f0e" : "#9467bd");
      mark(m.z / U, m.x / U, col, m.label, m.kind === "unreachable" ? "diamond" : "circle");
    }
    for (k = 0; k < F.issues.length; k++) {
      var iss = F.issues[k];
      if (iss.move >= 0) mark(z1[iss.move], x1[iss.move], "#d62728", "line " + iss.line, "x");
    }
  }
  function frameFor(step) {
    var K = D.keyframes, best = 0;
    for (var k = 0; k < K.length; k++) if (K[k].n <= step) best = k;
    return best;
  }
  var pending = false;
  function redraw() {
    if (pending) return;
    pending = true;
    window.requestAnimationFrame(function () { pending = false; draw(); });
  }
  function draw() {
    var r = dpr();
    ctx.setTransform(r, 0, 0, r, 0, 0);
    ctx.clearRect(0, 0, cv.width, cv.height);
    // axis
    ctx.strokeStyle = "#888"; ctx.lineWidth = 0.8; ctx.setLineDash([8, 3, 2, 3]);
    ctx.beginPath(); ctx.moveTo(0, sy(0)); ctx.lineTo(cv.width, sy(0)); ctx.stroke();
    ctx.setLineDash([]);
    if (state.layers.stock) fillRings(D.stock, "#eeeeee", "#999", 0.8);
    if (state.layers.material) {
      var f = D.keyframes[state.frame];
      fillRings(f.rings, "#cfe3f5", "#1f4e79", 1);
    }
    drawChuck(D.chuck);
    if (state.layers.model) drawModel();
    if (state.layers.path) drawPath(); else state.drawn = 0;
    if (state.layers.findings) drawFindings();
    drawHighlight(state.selected, "#ff00aa", 3);
    if (state.hover >= 0) drawHighlight([state.hover], "#000", 2.5);
    if (state.step > 0 && state.step <= N) {
      var k = state.step - 1;
      ctx.beginPath(); ctx.arc(sx(z1[k]), sy(x1[k]), 4, 0, 2 * Math.PI);
      ctx.fillStyle = "#000"; ctx.fill();
    }
    document.getElementById("drawn").textContent = state.drawn + " of " + N + " moves drawn";
  }

  // ---- program text (virtual list) -----------------------------------------------------
  var LINES = D.program.lines;
  var LH = 18;
  var box = document.getElementById("prog");
  var inner = document.getElementById("prog-inner");
  inner.style.height = (LINES.length * LH) + "px";
  function renderLines() {
    var top = box.scrollTop, h = box.clientHeight || 600;
    var a = Math.max(0, Math.floor(top / LH) - 5), b = Math.min(LINES.length, Math.ceil((top + h) / LH) + 5);
    var html = [];
    for (var n = a; n < b; n++) {
      var ln = n + 1;
      var cls = "pl" + (ln === state.selectedLine ? " sel" : "") + (ln === state.hoverLine ? " hov" : "") +
                (byLine[ln] ? " has" : "");
      html.push('<div class="' + cls + '" data-line="' + ln + '" style="top:' + (n * LH) + 'px">' +
                '<span class="ln">' + ln + '</span>' + esc(LINES[n]) + '</div>');
    }
    inner.innerHTML = html.join("");
  }
  function esc(s) {
    return s.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
  }
  function scrollToLine(ln) {
    var y = (ln - 1) * LH, top = box.scrollTop, h = box.clientHeight;
    if (y < top || y + LH > top + h) box.scrollTop = Math.max(0, y - h / 3);
  }
  box.addEventListener("scroll", renderLines);
  inner.addEventListener("click", function (ev) {
    var el = ev.target.closest ? ev.target.closest(".pl") : null;
    if (el) selectLine(parseInt(el.getAttribute("data-line"), 10));
  });
  function selectLine(ln) {
    state.selectedLine = ln;
    state.selected = (byLine[ln] || []).slice();
    info(state.selected.length ? ("line " + ln + ": " + state.selected.length + " move(s) selected")
                               : ("line " + ln + ": no moves"));
    renderLines();
    redraw();
  }

  // ---- hover / zoom / pan ----------------------------------------------------------------
  function nearest(pxX, pxY, tolPx) {
    var z = wz(pxX), x = wx(pxY), tol = tolPx / view.s, best = -1, bd = tol;
    for (var k = 0; k < N; k++) {
      if (M.k[k] === 0 && !state.layers.rapid) continue;
      var d;
      if (M.k[k] === 2 && arcC[k]) {
        var a = arcC[k], r = Math.hypot(x0[k] - a[1], z0[k] - a[0]);
        var ang = Math.atan2(x - a[1], z - a[0]);
        var s0 = Math.atan2(x0[k] - a[1], z0[k] - a[0]), s1 = Math.atan2(x1[k] - a[1], z1[k] - a[0]);
        var sweep = a[2] === 1 ? s0 - s1 : s1 - s0;
        while (sweep <= 0) sweep += 2 * Math.PI;
        var rel = a[2] === 1 ? s0 - ang : ang - s0;
        while (rel < 0) rel += 2 * Math.PI;
        while (rel >= 2 * Math.PI) rel -= 2 * Math.PI;
        if (rel <= sweep) d = Math.abs(Math.hypot(x - a[1], z - a[0]) - r);
        else d = Math.min(Math.hypot(z - z0[k], x - x0[k]), Math.hypot(z - z1[k], x - x1[k]));
      } else {
        var dz = z1[k] - z0[k], dx = x1[k] - x0[k], L2 = dz * dz + dx * dx;
        var t = L2 > 0 ? Math.max(0, Math.min(1, ((z - z0[k]) * dz + (x - x0[k]) * dx) / L2)) : 0;
        d = Math.hypot(z - (z0[k] + t * dz), x - (x0[k] + t * dx));
      }
      if (d <= bd) { bd = d; best = k; }
    }
    return best;
  }
  var drag = null, hoverQueued = null;
  cv.addEventListener("mousedown", function (ev) { drag = {x: ev.clientX, y: ev.clientY, cz: view.cz, cx: view.cx, moved: false}; });
  window.addEventListener("mouseup", function (ev) {
    if (drag && !drag.moved) {
      var r = cv.getBoundingClientRect();
      var k = nearest(ev.clientX - r.left, ev.clientY - r.top, 6);
      if (k >= 0) { selectLine(M.l[k]); scrollToLine(M.l[k]); }
    }
    drag = null;
  });
  cv.addEventListener("mousemove", function (ev) {
    if (drag) {
      var ddx = ev.clientX - drag.x, ddy = ev.clientY - drag.y;
      if (Math.abs(ddx) + Math.abs(ddy) > 3) drag.moved = true;
      view.cz = drag.cz - ddx / view.s; view.cx = drag.cx + ddy / view.s;
      redraw();
      return;
    }
    var r = cv.getBoundingClientRect();
    var q = [ev.clientX - r.left, ev.clientY - r.top];
    if (hoverQueued) { hoverQueued = q; return; }
    hoverQueued = q;
    window.requestAnimationFrame(function () {
      var p = hoverQueued; hoverQueued = null;
      hoverAt(p[0], p[1]);
    });
  });
  function hoverAt(px, py) {
    var k = nearest(px, py, 6);
    if (k !== state.hover) {
      state.hover = k;
      state.hoverLine = k >= 0 ? M.l[k] : 0;
      if (k >= 0) {
        scrollToLine(M.l[k]);
        info("move " + (k + 1) + ": " + KIND[M.k[k]] + " " + M.ops[M.g[k]] + ", line " + M.l[k] +
             (M.f[k] ? ", F " + M.f[k] + " mm/min" : "") + ", ends X" + (2 * x1[k]).toFixed(3) +
             " Z" + z1[k].toFixed(3) + " at " + clock(M.t[k] / 100));
      }
      renderLines();
      redraw();
    }
  }
  cv.addEventListener("mouseleave", function () { if (state.hover >= 0) { state.hover = -1; state.hoverLine = 0; renderLines(); redraw(); } });
  cv.addEventListener("wheel", function (ev) {
    ev.preventDefault();
    var r = cv.getBoundingClientRect(), px = ev.clientX - r.left, py = ev.clientY - r.top;
    var z = wz(px), x = wx(py);
    var f = Math.exp(-ev.deltaY * 0.0015);
    view.s *= f;
    view.cz = z - (px - cv.width / dpr() / 2) / view.s;
    view.cx = x - (cv.height / dpr() / 2 - py) / view.s;
    redraw();
  }, {passive: false});

  // ---- step-through -----------------------------------------------------------------------
  var slider = document.getElementById("step");
  slider.max = N; slider.value = N;
  function clock(s) {
    var m = Math.floor(s / 60), r = s - 60 * m;
    return m + ":" + (r < 10 ? "0" : "") + r.toFixed(1);
  }
  function setStep(n) {
    n = Math.max(0, Math.min(N, n | 0));
    state.step = n;
    state.frame = frameFor(n);
    slider.value = n;
    var t = n > 0 ? M.t[n - 1] / 100 : 0;
    document.getElementById("clock").textContent = clock(t) + " of " + clock(D.cycle_time_s);
    document.getElementById("stepinfo").textContent = "move " + n + " of " + N +
      (n > 0 ? " (line " + M.l[n - 1] + ": " + LINES[M.l[n - 1] - 1] + ")" : "") +
      "; material after move " + D.keyframes[state.frame].n;
    if (n > 0) { state.hoverLine = M.l[n - 1]; scrollToLine(M.l[n - 1]); renderLines(); }
    redraw();
  }
  slider.addEventListener("input", function () { setStep(parseInt(slider.value, 10)); });
  var playBtn = document.getElementById("play");
  function tick() {
    if (!state.playing) return;
    var inc = Math.max(1, Math.ceil(N / 600));
    if (state.step >= N) { state.playing = false; playBtn.textContent = "Play"; return; }
    setStep(state.step + inc);
    window.setTimeout(function () { window.requestAnimationFrame(tick); }, 30);
  }
  playBtn.addEventListener("click", function () {
    state.playing = !state.playing;
    playBtn.textContent = state.playing ? "Pause" : "Play";
    if (state.playing) { if (state.step >= N) setStep(0); tick(); }
  });
  document.getElementById("fit").addEventListener("click", fit);
  var boxes = document.querySelectorAll("input[data-layer]");
  for (i = 0; i < boxes.length; i++) {
    boxes[i].addEventListener("change", function (ev) {
      state.layers[ev.target.getAttribute("data-layer")] = ev.target.checked;
      redraw();
    });
  }
  function info(s) { document.getElementById("info").textContent = s; }

  // legend
  var leg = [];
  for (i = 0; i < M.ops.length; i++) {
    leg.push('<span class="lg"><i style="border-color:' + opColour[i] + (M.ops[i] === "rapid" ? ';border-style:dashed' : '') +
             '"></i>' + esc(M.ops[i] === "rapid" ? "rapid (G00)" : "feed " + M.ops[i]) + "</span>");
  }
  document.getElementById("legend").innerHTML = leg.join("");

  // a reviewer's and a test's handle on the page
  window.hncReport = {
    moves: N,
    drawnMoves: function () { return state.drawn; },
    selectLine: selectLine,
    selectedMoves: function () { return state.selected.slice(); },
    setStep: setStep,
    step: function () { return state.step; },
    frame: function () { return D.keyframes[state.frame]; },
    lastFrame: function () { return D.keyframes[D.keyframes.length - 1]; },
    hoverAt: hoverAt,
    hoverLine: function () { return state.hoverLine; },
    toScreen: function (z, x) { var r = cv.getBoundingClientRect(); return [r.left + sx(z), r.top + sy(x)]; },
    endOf: function (k) { return [z1[k], x1[k]]; },
    lineOf: function (k) { return M.l[k]; },
    lineElement: function (ln) { scrollToLine(ln); renderLines(); return inner.querySelector('[data-line="' + ln + '"]'); },
    draw: draw,
    ready: false
  };
  window.addEventListener("resize", resize);
  resize();
  fit();
  setStep(N);
  renderLines();
  draw();
  window.hncReport.ready = true;
})();
