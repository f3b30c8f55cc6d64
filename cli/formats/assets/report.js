/* The interactive part of a cnc run report (cli/formats/html_report.py): the backplot in
   plotly.js, the program listing beside it, and the links between them. The data is the
   JSON of <script id="cnc-view">; coordinates and per-point line numbers and feeds come as
   base64 little-endian typed arrays (kernel.report.backplot). No network is used. */
(function () {
  "use strict";
  var ROW = 16; // listing row height, px (matches the CSS)
  var data = JSON.parse(document.getElementById("cnc-view").textContent);
  var source = data.listing || [];
  var viewDiv = document.getElementById("cnc-plot");
  var listing = document.getElementById("cnc-listing");
  var rowsDiv = document.getElementById("cnc-rows");
  var status = document.getElementById("cnc-selected");
  var selected = 0;
  var hovered = 0;
  var traces = [];
  var highlightIndex = -1;
  var byLine = null;

  function bytes(b64) {
    var s = atob(b64);
    var u = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
    return u.buffer;
  }
  function floats(b64) {
    var f = new Float32Array(bytes(b64));
    var out = new Array(f.length);
    for (var i = 0; i < f.length; i++) out[i] = isNaN(f[i]) ? null : f[i];
    return out;
  }
  function ints(b64) {
    return new Int32Array(bytes(b64));
  }

  /* ---- listing: only the rows in sight are in the DOM ---- */
  function renderRows() {
    if (!listing) return;
    var first = Math.max(0, Math.floor(listing.scrollTop / ROW) - 20);
    var last = Math.min(source.length, first + Math.ceil(listing.clientHeight / ROW) + 40);
    var html = [];
    for (var i = first; i < last; i++) {
      var n = i + 1;
      var cls = "ln" + (n === selected ? " sel" : "") + (n === hovered ? " hov" : "");
      html.push('<div class="' + cls + '" data-line="' + n + '"><span class="no">' + n +
        "</span>" + escapeHtml(source[i]) + "</div>");
    }
    rowsDiv.style.top = first * ROW + "px";
    rowsDiv.innerHTML = html.join("");
  }
  function escapeHtml(s) {
    return s.replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
  }
  function scrollListing(n) {
    if (!listing || n < 1 || n > source.length) return;
    var top = (n - 1) * ROW;
    if (top < listing.scrollTop || top > listing.scrollTop + listing.clientHeight - ROW) {
      listing.scrollTop = Math.max(0, top - listing.clientHeight / 2);
    }
    renderRows();
  }

  /* ---- the view ---- */
  function indexLines() {
    byLine = new Map();
    for (var t = 0; t < traces.length; t++) {
      var lines = traces[t].lines;
      for (var i = 0; i < lines.length; i++) {
        var n = lines[i];
        if (!n) continue;
        var list = byLine.get(n);
        if (!list) byLine.set(n, (list = []));
        list.push(t, i);
      }
    }
  }
  function highlight(n) {
    if (highlightIndex < 0) return 0;
    if (!byLine) indexLines();
    var hit = byLine.get(n) || [];
    var dims = data.dim === 3 ? ["x", "y", "z"] : ["x", "y"];
    var out = { x: [], y: [], z: [] };
    for (var k = 0; k < hit.length; k += 2) {
      var tr = traces[hit[k]];
      var i = hit[k + 1];
      var from = i > 0 && tr.lines[i - 1] !== 0 && tr.x[i - 1] !== null ? i - 1 : i;
      for (var j = from; j <= i; j++) dims.forEach(function (d) { out[d].push(tr[d][j]); });
      dims.forEach(function (d) { out[d].push(null); });
    }
    var upd = { x: [out.x], y: [out.y] };
    if (data.dim === 3) upd.z = [out.z];
    Plotly.restyle(viewDiv, upd, [highlightIndex]);
    return hit.length / 2;
  }
  function select(n) {
    selected = n;
    scrollListing(n);
    var moves = typeof Plotly !== "undefined" ? highlight(n) : 0;
    if (status) {
      status.textContent = "line " + n + (moves ? ": its move is drawn in red" : ": no move on this line");
    }
  }

  function draw() {
    if (typeof Plotly === "undefined") {
      viewDiv.innerHTML = '<p class="error">The view needs ' + data.library +
        " beside this page (cnc run writes it there).</p>";
      return;
    }
    var plot = [];
    var three = data.dim === 3;
    var kind = three ? "scatter3d" : "scattergl";
    data.traces.forEach(function (t) {
      var tr = { x: floats(t.x), y: floats(t.y), lines: ints(t.line) };
      if (three) tr.z = floats(t.z);
      var feeds = new Float32Array(bytes(t.feed));
      var custom = new Array(tr.lines.length);
      for (var i = 0; i < custom.length; i++) {
        custom[i] = [tr.lines[i], t.rapid ? "rapid" : "F" + +feeds[i].toFixed(1)];
      }
      traces.push(tr);
      var p = {
        type: kind, mode: "lines", name: t.name, x: tr.x, y: tr.y, customdata: custom,
        line: { color: t.color, width: t.width, dash: t.dash },
        hovertemplate: "line %{customdata[0]} · %{customdata[1]}<extra>%{fullData.name}</extra>",
        connectgaps: false
      };
      if (three) p.z = tr.z;
      plot.push(p);
    });
    data.boxes.forEach(function (b) {
      var p = {
        type: kind, mode: "lines", name: b.name, x: floats(b.x), y: floats(b.y),
        line: { color: b.color, width: 2, dash: b.dash }, hoverinfo: "skip", connectgaps: false,
        visible: b.shown ? true : "legendonly"
      };
      if (three) p.z = floats(b.z);
      plot.push(p);
    });
    if (data.surface && three) {
      var s = data.surface;
      var z = floats(s.z);
      var rows = [];
      for (var j = 0; j < s.ny; j++) rows.push(z.slice(j * s.nx, (j + 1) * s.nx));
      var xs = [], ys = [];
      for (var i = 0; i < s.nx; i++) xs.push(s.x0 + (i + 0.5) * (s.x1 - s.x0) / s.nx);
      for (var j2 = 0; j2 < s.ny; j2++) ys.push(s.y0 + (j2 + 0.5) * (s.y1 - s.y0) / s.ny);
      var part = {
        type: "surface", name: "cut part", x: xs, y: ys, z: rows, showscale: false,
        colorscale: [[0, "#5b6b7c"], [1, "#d9dee5"]], opacity: 0.85, hoverinfo: "skip"
      };
      var dv = s.deviation;
      if (dv) { // coloured by stock - design: red below it, blue above, grey within tolerance
        var d = floats(dv.values);
        var drows = [];
        for (var j3 = 0; j3 < s.ny; j3++) drows.push(d.slice(j3 * s.nx, (j3 + 1) * s.nx));
        part.surfacecolor = drows;
        var cols = []; // the hover label reads customdata column-major: [x index][y index]
        for (var i3 = 0; i3 < s.nx; i3++) {
          var col = [];
          for (var j4 = 0; j4 < s.ny; j4++) col.push(d[j4 * s.nx + i3]);
          cols.push(col);
        }
        part.customdata = cols;
        part.colorscale = dv.colorscale;
        part.cmin = -dv.span;
        part.cmax = dv.span;
        part.opacity = 1;
        part.showscale = true;
        part.name = "cut part (stock - design)";
        part.colorbar = { title: { text: "stock - design (mm)" }, len: 0.7, x: 1.0 };
        part.hovertemplate = "X%{x:.2f} Y%{y:.2f} Z%{z:.3f}<br>deviation %{customdata:.3f} mm" +
          "<extra></extra>";
        delete part.hoverinfo;
      }
      plot.push(part);
      if (dv && dv.marks.length) {
        plot.push({
          type: "scatter3d", mode: "markers+text", name: "worst deviation",
          x: dv.marks.map(function (m) { return m.x; }),
          y: dv.marks.map(function (m) { return m.y; }),
          z: dv.marks.map(function (m) { return m.z; }),
          text: dv.marks.map(function (m) { return m.label; }),
          customdata: dv.marks.map(function (m) { return [m.line, m.value]; }),
          marker: { size: 6, symbol: "diamond", color: dv.marks.map(function (m) { return m.color; }),
            line: { color: "#000000", width: 1 } },
          textposition: "top center",
          hovertemplate: "%{text}<br>line %{customdata[0]}<extra></extra>"
        });
      }
    }
    var hl = { type: kind, mode: "lines", name: "selected line", x: [], y: [],
      line: { color: "#e4002b", width: 10 }, hoverinfo: "skip", connectgaps: false,
      showlegend: false };
    if (three) hl.z = [];
    highlightIndex = plot.length;
    plot.push(hl);
    var layout = {
      margin: { l: 0, r: 0, t: 0, b: 0 }, showlegend: true,
      legend: { x: 0, y: 1, bgcolor: "rgba(255,255,255,0.7)" }, uirevision: "keep"
    };
    if (three) {
      layout.scene = {
        aspectmode: "data",
        camera: { eye: { x: 0.7, y: -1.6, z: 1.1 } }, // from the front, right and above
        dragmode: "orbit",
        xaxis: { title: { text: data.labels[0] } },
        yaxis: { title: { text: data.labels[1] } },
        zaxis: { title: { text: data.labels[2] } }
      };
    } else {
      layout.margin = { l: 60, r: 10, t: 10, b: 50 };
      layout.xaxis = { title: { text: data.labels[0] } };
      layout.yaxis = { title: { text: data.labels[1] }, scaleanchor: "x" };
    }
    Plotly.newPlot(viewDiv, plot, layout, { responsive: true, displaylogo: false });
    viewDiv.on("plotly_hover", function (ev) {
      var p = ev.points && ev.points[0];
      if (p && p.customdata) {
        hovered = p.customdata[0];
        scrollListing(hovered);
      }
    });
    viewDiv.on("plotly_click", function (ev) {
      var p = ev.points && ev.points[0];
      if (p && p.customdata) select(p.customdata[0]);
    });
  }

  if (listing) {
    var digits = String(source.length).length;
    var style = document.createElement("style");
    style.textContent = ".ln .no{width:" + (digits + 1) + "ch}";
    document.head.appendChild(style);
    document.getElementById("cnc-spacer").style.height = source.length * ROW + "px";
    listing.addEventListener("scroll", renderRows);
    renderRows();
  }
  document.addEventListener("click", function (ev) {
    var el = ev.target.closest ? ev.target.closest("[data-line]") : null;
    if (el) select(parseInt(el.getAttribute("data-line"), 10));
  });
  draw();
  window.cncReport = { select: select, traces: traces };

  /* ---- the servo trace charts (kernel.report.charts), after the backplot ---- */
  window.cncDrawCharts = function () {
    var el = document.getElementById("cnc-charts");
    if (!el) return;
    var config = { responsive: true, displaylogo: false };
    JSON.parse(el.textContent).forEach(function (c, i) {
      var div = document.getElementById("cnc-chart-" + i);
      if (!div) return;
      if (c.kind === "xy") {
        var plot = [
          { type: "scattergl", mode: "lines", name: "commanded", x: floats(c.x_cmd),
            y: floats(c.y_cmd), line: { color: "#bbb", width: 4 } },
          { type: "scattergl", mode: "markers", name: "actual", x: floats(c.x_act),
            y: floats(c.y_act),
            marker: { size: 3, color: floats(c.error), colorscale: "Viridis", showscale: true,
                      colorbar: { title: { text: c.error_label } } } }
        ];
        if (c.worst) {
          plot.push({ type: "scatter", mode: "markers+text", name: "worst",
            x: [c.worst[0]], y: [c.worst[1]], text: ["max " + c.worst[2].toPrecision(3) + " µm"],
            textposition: "bottom right",
            marker: { size: 16, color: "rgba(0,0,0,0)", line: { color: "#d62728", width: 2 } } });
        }
        Plotly.newPlot(div, plot, { title: { text: c.title }, margin: { t: 60, r: 20 },
          legend: { orientation: "h", x: 0, y: 1.06 },
          xaxis: { title: { text: "X [mm]" } },
          yaxis: { title: { text: "Y [mm]" }, scaleanchor: "x" } }, config);
        return;
      }
      var t = floats(c.t);
      var traces = [];
      var layout = { title: { text: c.title }, margin: { t: 40, r: 20 }, showlegend: true,
                     xaxis: { title: { text: "time [s]" }, anchor: "y3" } };
      var colours = ["#1f77b4", "#ff7f0e", "#d62728"];
      c.rows.forEach(function (row, k) {
        var axis = k === 0 ? "y" : "y" + (k + 1);
        var top = 1 - k / 3;
        layout[k === 0 ? "yaxis" : "yaxis" + (k + 1)] = {
          title: { text: row.label }, domain: [top - 1 / 3 + 0.06, top], anchor: "x" };
        if (row.cmd) {
          traces.push({ type: "scattergl", mode: "lines", name: "commanded (dashed)",
            legendgroup: "cmd", showlegend: k === 0, x: t, y: floats(row.cmd), yaxis: axis,
            line: { color: "#222", dash: "dash", width: 2 } });
        }
        traces.push({ type: "scattergl", mode: "lines", name: k === 2 ? "error" : "actual",
          legendgroup: k === 2 ? "err" : "act", showlegend: k !== 1, x: t, y: floats(row.act),
          yaxis: axis, line: { color: colours[k], width: 1.2 } });
      });
      Plotly.newPlot(div, traces, layout, config);
    });
  };
})();
