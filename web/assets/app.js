// The live view: takes the server's `update` events and shows them.
// Every value goes in as text (textContent), never as markup.
"use strict";

(function () {
  const token = new URLSearchParams(window.location.search).get("token");
  const query = token ? "?token=" + encodeURIComponent(token) : "";
  const AXES = ["X", "Y", "Z", "A", "B", "C", "U", "V"];

  function byId(id) { return document.getElementById(id); }

  function setText(id, text) {
    const el = byId(id);
    if (el && el.textContent !== text) { el.textContent = text; }
  }

  function el(tag, cls, text) {
    const e = document.createElement(tag);
    if (cls) { e.className = cls; }
    if (text !== undefined) { e.textContent = text; }
    return e;
  }

  function mm(v) { return v.toFixed(4); }

  function showClock(c) {
    setText("clock", c.mode === "realtime" ? "real time ×" + c.factor : "stepped");
  }

  function showQueue(q) {
    setText("queue", String(q.waiting));
    setText("queue-capacity", String(q.capacity));
    const share = q.capacity > 0 ? Math.min(1, q.waiting / q.capacity) : 0;
    byId("queue-bar").style.width = (share * 100).toFixed(1) + "%";
  }

  function toolTable(g) {
    const t = el("table", "tools");
    const head = el("tr");
    ["entry", "radius", "length", "wear", "OTC wear"].forEach(function (h) {
      head.appendChild(el("th", null, h));
    });
    t.appendChild(head);
    g.tools.forEach(function (tool) {
      const row = el("tr", tool.index === g.wkz ? "current" : null);
      const base = "tool-" + g.index + "-" + tool.index + "-";
      row.appendChild(el("td", null, String(tool.index)));
      [["radius", tool.radius], ["length", tool.length], ["wear", tool.wear],
       ["otc-wear", tool.otc_wear]].forEach(function (f) {
        const td = el("td", null, f[1] === null ? "–" : mm(f[1]));
        td.id = base + f[0];
        row.appendChild(td);
      });
      t.appendChild(row);
    });
    return t;
  }

  function register(label, id, value, bits, bad) {
    const line = el("div", "reg", label + " ");
    const v = el("b", null, String(value));
    v.id = id;
    line.appendChild(v);
    const b = el("span", "bits" + (bad && bits.length ? " bad" : ""),
      bits.length ? bits.join(" | ") : "none");
    b.id = id + "-bits";
    line.appendChild(b);
    return line;
  }

  function otcLine(g) {
    const o = g.otc;
    const text = "OTC " + (o.on ? "on" : "off") + ", type " + o.proc_type + ", mode " + o.mode +
      ", running wear " + mm(o.running_wear) + " mm" + (o.error ? ", OtcError " + o.error : "");
    const d = el("div", "otc", text);
    d.id = "otc-" + g.index;
    return d;
  }

  let shownGroups = "";

  function showGroups(groups) {
    const json = JSON.stringify(groups);
    if (json === shownGroups) { return; }
    shownGroups = json;
    const box = byId("groups");
    const parts = [];
    if (groups.length === 0) { parts.push(el("p", "none", "no group in use")); }
    groups.forEach(function (g) {
      const d = el("div", "group");
      d.appendChild(el("h3", null, "Group " + g.index + " — WKZINDEX " + g.wkz));
      d.appendChild(register("STATUS", "status-" + g.index, g.status, g.status_bits, false));
      d.appendChild(register("ERROR", "error-" + g.index, g.error, g.error_bits, true));
      d.appendChild(toolTable(g));
      if (g.otc) { d.appendChild(otcLine(g)); }
      parts.push(d);
    });
    box.replaceChildren.apply(box, parts);
  }

  function showState(s) {
    showClock(s.clock);
    s.axes.forEach(function (a) { setText("pos-" + a.name, mm(a.pos)); });
    showQueue(s.queue);
    showGroups(s.groups);
    setText("clients-uoi", String(s.clients.uoi));
    setText("clients-opcua", s.clients.opcua === null ? "n/a" : String(s.clients.opcua));
    setText("clients-web", String(s.clients.web));
    setText("path-axes", AXES[s.plane.h] + " across, " + AXES[s.plane.v] + " up");
    window.addiposDraw.machine(s.axes[s.plane.h].pos, s.axes[s.plane.v].pos);
  }

  function connect() {
    const link = byId("link");
    const source = new EventSource("/events" + query);
    source.addEventListener("open", function () {
      link.textContent = "live";
      link.className = "link live";
    });
    source.addEventListener("error", function () {
      link.textContent = "reconnecting…";
      link.className = "link lost";
    });
    source.addEventListener("update", function (e) {
      const u = JSON.parse(e.data);
      window.addiposDraw.add(u.path.spooled, u.path.executed);
      if (u.state) { showState(u.state); }
      const n = window.addiposDraw.counts();
      setText("path-count", n.spooled + " elements, " + n.executed + " positions");
    });
  }

  connect();
})();
