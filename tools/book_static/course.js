/* The course book's own script (tools/book.py loads it on every page). */
(function () {
  "use strict";
  const narrow = () => window.matchMedia("(max-width: 700px), (pointer: coarse)").matches;

  /* A 3-D figure on a phone or touch screen: a swipe over it scrolls the page. A shield
     covers it with one button, "Turn the figure", which lifts the shield; "Done" puts it
     back. On a laptop with a mouse the figure turns at once, as before. */
  function shield(fig) {
    const holder = fig.parentElement;
    if (!holder || holder.querySelector(":scope > .course-figure-shield")) return;
    if (getComputedStyle(holder).position === "static") holder.style.position = "relative";
    const cover = document.createElement("div");
    cover.className = "course-figure-shield";
    const turn = document.createElement("button");
    turn.type = "button";
    turn.textContent = "Turn the figure";
    cover.appendChild(turn);
    const done = document.createElement("button");
    done.type = "button";
    done.className = "course-figure-done";
    done.textContent = "Done: scroll the page";
    done.hidden = true;
    turn.addEventListener("click", () => { cover.hidden = true; done.hidden = false; });
    done.addEventListener("click", () => { cover.hidden = false; done.hidden = true; });
    holder.appendChild(cover);
    holder.appendChild(done);
    // the shield stops above the play buttons and the slider, which work as they are
    const place = () => {
      const top = holder.getBoundingClientRect().top;
      const controls = [...fig.querySelectorAll(".slider-container, .updatemenu-container")]
        .map(c => c.getBoundingClientRect().top - top).filter(y => y > 40);
      cover.style.bottom = controls.length ? (holder.clientHeight - Math.min(...controls)) + "px" : "0";
      done.style.bottom = cover.style.bottom;
    };
    whenDrawn(fig, () => { place(); if (fig.on) fig.on("plotly_afterplot", place); });
  }

  function whenDrawn(fig, then, tries = 0) {
    if (fig._fullLayout && fig.querySelector(".main-svg")) then();
    else if (tries < 100) setTimeout(() => whenDrawn(fig, then, tries + 1), 200);
  }

  /* A 3-D figure is laid out for the width it has on the page (its layout was made for a
     projected slide, as tools/book.py relays it out for paper): smaller fonts and fewer
     ticks, room under the slider for its numbers, the current value clear of the buttons;
     on a phone the legend goes above the scene, and a long title is broken into lines. */
  function fitFigure(fig) {
    whenDrawn(fig, () => {
      if (!window.Plotly || fig.dataset.courseFitted) return;
      fig.dataset.courseFitted = "1";
      const L = fig._fullLayout, w = fig.clientWidth, phone = w < 560;
      const f = phone ? 10 : 12;
      const upd = {"font.size": f + 1, "legend.font.size": f + 1, "margin.l": 4, "margin.r": 4};
      let top = (L.margin && L.margin.t) || 60, extra = 0;
      const title = fig.layout && fig.layout.title;
      const text = title && (typeof title === "string" ? title : title.text);
      if (text && !text.includes("<br>") && phone) {
        const perLine = Math.max(20, Math.floor(w / 8));
        const lines = [""];
        for (const word of text.split(" ")) {
          const last = lines[lines.length - 1];
          if (last && (last + " " + word).replace(/<[^>]+>/g, "").length > perLine) lines.push(word);
          else lines[lines.length - 1] = last ? last + " " + word : word;
        }
        if (lines.length > 1) { upd["title.text"] = lines.join("<br>"); top = Math.max(top, 18 * lines.length + 20); }
      }
      upd["title.font.size"] = phone ? 13 : 15;
      for (const sc of Object.keys(L).filter(k => /^scene\d*$/.test(k))) {
        for (const a of ["xaxis", "yaxis", "zaxis"]) {
          upd[`${sc}.${a}.tickfont.size`] = f;
          upd[`${sc}.${a}.title.font.size`] = f + 2;
          upd[`${sc}.${a}.nticks`] = phone ? 3 : 5;
        }
      }
      if (L.showlegend !== false && phone) {
        Object.assign(upd, {"legend.orientation": "h", "legend.x": 0, "legend.xanchor": "left",
                            "legend.y": 1, "legend.yanchor": "bottom", "legend.font.size": f});
        // a legend's title above its entries, not before them on a row wider than a phone
        if (L.legend && L.legend.title && L.legend.title.text) upd["legend.title.side"] = "top";
        extra += 66;
        // a lone scene kept clear of a legend at its side (a slide's layout) takes the
        // whole width once the legend is above it
        const scenes = Object.keys(L).filter(k => /^scene\d*$/.test(k));
        const d = scenes.length === 1 && L[scenes[0]].domain && L[scenes[0]].domain.x;
        if (d && (d[0] > 0 || d[1] < 1)) upd[`${scenes[0]}.domain.x`] = [0, 1];
      }
      if (L.sliders && L.sliders.length) {
        upd["sliders[0].font.size"] = phone ? 9 : 11;
        upd["sliders[0].currentvalue.font.size"] = f + 1;
        upd["sliders[0].currentvalue.xanchor"] = "right";
        upd["margin.b"] = ((L.margin && L.margin.b) || 0) + 36;
        extra += 36;
      }
      if (L.updatemenus && L.updatemenus.length) upd["updatemenus[0].font.size"] = f;
      upd["margin.t"] = top + (phone && L.showlegend !== false ? 66 : 0);
      upd.height = (L.height || fig.clientHeight) + extra;
      // the figure's box was sized for its first layout: it grows with it
      for (const box of [fig, fig.parentElement]) {
        if (box && box.style.height && !box.classList.contains("cell_output")) box.style.height = upd.height + "px";
      }
      const drawn = window.Plotly.relayout(fig, upd);
      // labels written in the scene (a point's name) at the size of the rest of the text:
      // at a slide's size they run past a phone's edge
      const labelled = (fig.data || []).map((t, i) => /text/.test(t.mode || "") ? i : -1).filter(i => i >= 0);
      if (phone && labelled.length) window.Plotly.restyle(fig, {"textfont.size": f + 3, textposition: "top right"}, labelled);
      // a slide's camera was placed for a wide scene: on a phone it is moved back until
      // everything drawn lies inside the narrow frame, and the frame loses the height the
      // drawing no longer needs
      if (phone) {
        Promise.resolve(drawn).then(() => fitScenes(fig, f + 3))
          .finally(() => { fig.dataset.courseSceneFitted = "1"; });
      } else fig.dataset.courseSceneFitted = "1";
    });
  }

  /* The numbers of a plotly array: a plain or typed array, nested (a surface's rows), or
     plotly's packed form {dtype, bdata}. */
  function numbers(a, out = []) {
    if (a == null) return out;
    if (a.bdata && a.dtype) {
      const kinds = {f4: Float32Array, f8: Float64Array, i1: Int8Array, u1: Uint8Array, i2: Int16Array,
                     u2: Uint16Array, i4: Int32Array, u4: Uint32Array};
      const raw = Uint8Array.from(atob(a.bdata), c => c.charCodeAt(0));
      a = kinds[a.dtype] ? new kinds[a.dtype](raw.buffer) : [];
    }
    if (typeof a === "number") { out.push(a); return out; }
    for (const v of a) { if (v && typeof v === "object") numbers(v, out); else out.push(typeof v === "number" ? v : NaN); }
    return out;
  }

  /* What a 3-D scene draws, as points of the scene's own space, each with the room in
     pixels it needs around it [left, right, top, bottom]: the points of every trace in
     the scene (in every frame of an animation), a label's text beside its point, and the
     axis box with its tick labels when the box is drawn. */
  function sceneContent(fig, name, scene, textSize) {
    const scale = scene.dataScale || [1, 1, 1];
    const B = scene.glplot && scene.glplot.bounds;
    // what lies beyond the axes' ranges is not drawn: it counts at the range's end
    const clip = (v, i) => B ? Math.min(B[1][i], Math.max(B[0][i], v)) : v;
    const pts = [];
    const add = (t, room) => {
      const x = numbers(t.x), y = numbers(t.y), z = numbers(t.z);
      const grid = t.type === "surface" && z.length > x.length;      // x, y the grid's sides
      const rows = grid ? y.length : 0, cols = grid ? x.length : 0;
      for (let i = 0; i < z.length; i++) {
        const p = grid ? [x[i % cols], y[Math.floor(i / cols) % rows], z[i]] : [x[i], y[i], z[i]];
        if (p.every(Number.isFinite)) pts.push({p: p.map((v, k) => clip(v * scale[k], k)), room});
      }
    };
    const full = fig._fullData || [];
    const here = i => full[i] && (full[i].scene || "scene") === name && full[i].visible !== false;
    full.forEach((t, i) => {
      if (!here(i)) return;
      const marker = /markers/.test(t.mode || "") && t.marker ? (+t.marker.size || 6) / 2 : 0;
      const r = Math.max(8, marker, t.type === "cone" ? 12 : 0);
      const text = /text/.test(t.mode || "") && t.text ? t.text : null;
      if (!text) { add(t, [r, r, r, r]); return; }
      // a label: each point on its own, with its text's width at its side
      const x = numbers(t.x), y = numbers(t.y), z = numbers(t.z);
      const size = (t.textfont && +t.textfont.size) || textSize;
      const pos = String(t.textposition || "middle center");
      x.forEach((_, k) => {
        const label = String((Array.isArray(text) ? text[k] : text) || "").replace(/<[^>]+>/g, "");
        const w = label ? 0.6 * size * label.length + 4 : 0, h = label ? size + 4 : 0;
        const room = [r + (/left/.test(pos) ? w : /right/.test(pos) ? 0 : w / 2),
                      r + (/right/.test(pos) ? w : /left/.test(pos) ? 0 : w / 2),
                      r + (/top/.test(pos) ? h : 0), r + (/bottom/.test(pos) ? h : 0)];
        add({x: [x[k]], y: [y[k]], z: [z[k]]}, room);
      });
    });
    const frames = (fig._transitionData && fig._transitionData._frames) || [];
    for (const fr of frames) {
      (fr.data || []).forEach((d, j) => {
        const i = fr.traces ? fr.traces[j] : j;
        if (here(i) && d) add({x: d.x, y: d.y, z: d.z, type: full[i].type}, [8, 8, 8, 8]);
      });
    }
    const L = fig._fullLayout[name];
    const box = ["xaxis", "yaxis", "zaxis"].some(a => L[a].visible !== false &&
      (L[a].showgrid || L[a].showbackground || L[a].showline));
    if (box && B) {
      // the box's corners with room for the tick labels beyond them; the middle of each
      // edge along an axis with room for that axis' title too (plotly writes it there, on
      // the edge it chooses as the view turns)
      const ticks = 2 * textSize;
      for (const i of [0, 1]) for (const j of [0, 1]) for (const k of [0, 1])
        pts.push({p: [B[i][0], B[j][1], B[k][2]], room: [ticks, ticks, ticks, ticks]});
      ["xaxis", "yaxis", "zaxis"].forEach((a, i) => {
        const title = String((L[a].title && L[a].title.text) || "").replace(/<[^>]+>/g, "");
        if (!title || L[a].visible === false) return;
        const across = 3.5 * textSize + 0.6 * textSize * title.length, up = ticks + textSize;
        const [j, k] = [0, 1, 2].filter(n => n !== i);
        for (const u of [0, 1]) for (const v of [0, 1]) {
          const p = [0, 0, 0];
          p[i] = (B[0][i] + B[1][i]) / 2; p[j] = B[u][j]; p[k] = B[v][k];
          pts.push({p, room: [across, across, up, up]});
        }
      });
    }
    return pts;
  }

  /* Each 3-D scene of a figure on a phone: its camera moved back along its line of sight
     until all it draws lies in its frame (the view is the one the slide chose, only
     farther), then the frame as tall as the drawing needs (never taller than before). In
     plotly's perspective the height of the frame sets the scale: the vertical field of
     view is fixed, so a point's distance from the frame's centre in pixels is
     (h / 2) k y / depth, k = 1 / tan(fovy / 2). */
  function fitScenes(fig, textSize) {
    const L = fig._fullLayout;
    const names = Object.keys(L).filter(k => /^scene\d*$/.test(k));
    if (names.length !== 1) return;  // side by side scenes keep the slide's layout
    const name = names[0], sc = L[name], scene = sc._scene;
    const g = scene && scene.glplot, cp = g && g.cameraParams;
    if (!cp || !cp.view || !cp.model) return;
    const mul = (m, v) => [0, 1, 2, 3].map(i => m[i] * v[0] + m[4 + i] * v[1] + m[8 + i] * v[2] + m[12 + i] * v[3]);
    const content = sceneContent(fig, name, scene, textSize);
    if (!content.length) return;
    const seen = content.map(({p, room}) => {
      const v = mul(cp.view, mul(cp.model, [p[0], p[1], p[2], 1]));
      return {x: v[0], y: v[1], depth: -v[2], room};
    });
    const k = 1 / Math.tan((g.fovy || Math.PI / 4) / 2);
    const size = L._size, dx = sc.domain.x, dy = sc.domain.y;
    const w = size.w * (dx[1] - dx[0]), h0 = size.h * (dy[1] - dy[0]);
    // the move back that fits every point into a frame of height h, and the tallest frame
    // that still fits it across
    const back = (h, across = true) => Math.max(0, ...seen.map(({x, y, depth, room: [l, r, t, b]}) => Math.max(
      across ? k * (h / 2) * Math.max(x, 0) / Math.max(1, w / 2 - r) : 0,
      across ? k * (h / 2) * Math.max(-x, 0) / Math.max(1, w / 2 - l) : 0,
      k * (h / 2) * Math.max(y, 0) / Math.max(1, h / 2 - t), k * (h / 2) * Math.max(-y, 0) / Math.max(1, h / 2 - b)) - depth));
    const across = d => Math.min(...seen.map(({x, depth, room: [l, r]}) => {
      const need = k * Math.abs(x) / (2 * (depth + d));
      return need > 0 ? (w / 2 - (x > 0 ? r : l)) / need : Infinity;
    }));
    let h = h0, d = 0;
    for (let round = 0; round < 4; round++) {
      d = back(h, false);
      h = Math.min(h0, Math.max(0.75 * w, across(d)));
    }
    d = back(h);
    const upd = {};
    if (d > 1e-3) {
      const e = sc.camera.eye, c = sc.camera.center;
      const dist = Math.hypot(e.x - c.x, e.y - c.y, e.z - c.z), s = (dist + d) / dist;
      upd[`${name}.camera.eye`] = {x: c.x + s * (e.x - c.x), y: c.y + s * (e.y - c.y), z: c.z + s * (e.z - c.z)};
    }
    if (h0 - h > 8) {
      upd.height = Math.round(L.height - (h0 - h));
      for (const b of [fig, fig.parentElement]) {
        if (b && b.style.height && !b.classList.contains("cell_output")) b.style.height = upd.height + "px";
      }
    }
    if (Object.keys(upd).length) return window.Plotly.relayout(fig, upd);
  }
  // the print (tools/book.py) fits each scene to its frame on paper the same way, once the
  // figure has its paper's fonts and width
  window.courseFitScenes = fitScenes;

  /* A display formula wider than the column is set smaller until it fits, so that it keeps
     its equation number in view: down to 70% of the text's size when it then fits whole
     (MathJax sets display maths at about 127% of the text); one wider still is set at 80%
     of its own size and scrolls in its own box. Inline maths wider than its line scrolls
     in its own box. */
  function fitFormulas() {
    for (const m of document.querySelectorAll('.bd-article mjx-container[display="true"]')) {
      if (m.dataset.courseSize === undefined) m.dataset.courseSize = m.style.fontSize || "";
      m.style.fontSize = m.dataset.courseSize;
      // a numbered formula has a min-width (in em) that can exceed its column
      const avail = Math.max(1, m.parentElement ? m.parentElement.clientWidth : m.clientWidth);
      const over = Math.max(m.scrollWidth, m.offsetWidth) / avail;
      if (over > 1.01) {
        const base = parseFloat(m.dataset.courseSize) || 100;
        const text = parseFloat(getComputedStyle(m.closest("article") || document.body).fontSize);
        const least = 0.7 * text / parseFloat(getComputedStyle(m).fontSize);  // 70% of the text
        const fit = 1 / over - 0.01;
        m.style.fontSize = (base * (fit >= least ? fit : Math.max(0.8, fit))).toFixed(1) + "%";
      }
      m.classList.toggle("course-scrolls", Math.max(m.scrollWidth, m.offsetWidth) > avail + 1);
    }
    for (const m of document.querySelectorAll('.bd-article mjx-container:not([display="true"])')) {
      m.classList.remove("course-wide-inline");
      // (not its span.math: the theme makes it a flex box as wide as the formula)
      const box = m.closest("p, li, td, th, dd, dt, div, h1, h2, h3, h4, h5, h6") || m.parentElement;
      if (!box) continue;
      const b = box.getBoundingClientRect(), r = m.getBoundingClientRect();
      if (r.width > b.width - 2 || r.right > b.right + 1) m.classList.add("course-wide-inline");
    }
  }

  /* The colour-mode button switches between light and dark (the theme's third state,
     "auto", looks like one of them, so a click could seem to do nothing); its name says
     what a click does. */
  function themeToggle() {
    const root = document.documentElement;
    const label = btn => {
      const now = root.dataset.theme === "dark" ? "dark" : "light";
      const next = now === "dark" ? "light" : "dark";
      btn.setAttribute("aria-label", `Colour mode: ${now}. Switch to ${next}`);
      btn.setAttribute("title", `Switch to ${next} mode`);
    };
    for (const btn of document.querySelectorAll(".theme-switch-button")) {
      label(btn);
      btn.addEventListener("click", event => {
        event.stopImmediatePropagation();
        event.preventDefault();
        const next = root.dataset.theme === "dark" ? "light" : "dark";
        root.dataset.mode = next;
        root.dataset.theme = next;
        try { localStorage.setItem("mode", next); localStorage.setItem("theme", next); } catch (e) { /* private window */ }
        document.querySelectorAll(".theme-switch-button").forEach(label);
      }, true);
    }
  }

  /* The page's contents beside the text (taller than the window in a long chapter, they
     scroll in their own box) follow the reader: the entry of the section being read is
     marked "active" and brought into the box's view. The section being read is worked out
     from the scroll position after every scroll: the last one whose heading is above the
     window's top third (at the page's foot, the last whose heading is in the window). The
     theme's own marking follows headings as they cross the window's edge, and misses them
     when a jump (Home, End, a long wheel turn) carries them past it in one go. */
  function followContents() {
    const panel = document.querySelector(".bd-sidebar-secondary");
    if (!panel) return;
    const links = [...panel.querySelectorAll('a.nav-link[href^="#"]')];
    const targets = links.map(a => document.getElementById(decodeURIComponent(a.hash.slice(1))));
    const mark = () => {
      const line = window.innerHeight / 3;
      const atFoot = window.innerHeight + window.scrollY >= document.documentElement.scrollHeight - 2;
      let current = null, best = -Infinity;
      links.forEach((a, i) => {
        if (!targets[i]) return;
        const top = targets[i].getBoundingClientRect().top;
        if ((top <= line || (atFoot && top < window.innerHeight)) && top >= best) { best = top; current = a; }
      });
      // the entry and the entries it sits under
      const want = new Set();
      for (let li = current && current.closest("li"); li && panel.contains(li);
           li = li.parentElement.closest("li")) {
        const a = li.querySelector(":scope > a.nav-link");
        if (a) want.add(a);
      }
      for (const a of links) {
        if (want.has(a) !== a.classList.contains("active")) a.classList.toggle("active", want.has(a));
        // the theme's marker for screen readers and its bold, blue entry: the same entries
        if (want.has(a) && a.getAttribute("aria-current") !== "true") a.setAttribute("aria-current", "true");
        else if (!want.has(a) && a.hasAttribute("aria-current")) a.removeAttribute("aria-current");
      }
      // the theme marks an entry's li too, and leaves it marked when it loses track: only
      // the entries marked here keep theirs, so one place is marked, never two
      for (const li of panel.querySelectorAll("li")) {
        const a = li.querySelector(":scope > a.nav-link");
        const on = !!a && want.has(a);
        if (li.classList.contains("active") !== on) li.classList.toggle("active", on);
      }
    };
    const show = () => {
      mark();
      if (panel.scrollHeight <= panel.clientHeight + 1) return;
      // the deepest marked entry that is shown (a folded sub-list's entry has no box)
      const active = [...panel.querySelectorAll("a.active")].filter(a => a.getClientRects().length).pop();
      if (!active) return;
      const p = panel.getBoundingClientRect(), r = active.getBoundingClientRect();
      if (r.top < p.top + 48 || r.bottom > p.bottom - 48)
        panel.scrollTop += r.top - p.top - panel.clientHeight / 3;
    };
    let pending = null;
    const soon = () => { clearTimeout(pending); pending = setTimeout(show, 60); };
    new MutationObserver(soon).observe(panel, {subtree: true, attributes: true,
                                               attributeFilter: ["class", "aria-current"]});
    window.addEventListener("scroll", soon, {passive: true});
  }

  /* On a phone a picture drawn for a wider page (a legend beside its plot) is shrunk until
     its ticks are a few pixels tall: a tap opens it at full size, where it can be zoomed. */
  function zoomPictures() {
    if (!narrow()) return;
    const wrap = img => {
      if (document.body.dataset.coursePaper || img.closest("a") || !img.naturalWidth || img.naturalWidth < 1.25 * img.clientWidth) return;
      const a = document.createElement("a");
      a.className = "course-figure-zoom";
      a.href = img.currentSrc || img.src;
      a.target = "_blank";
      a.rel = "noopener";
      a.title = "Open the figure full size";
      img.before(a);
      a.appendChild(img);
    };
    for (const img of document.querySelectorAll(".bd-article div.cell_output img")) {
      if (img.complete) wrap(img); else img.addEventListener("load", () => wrap(img), {once: true});
    }
  }

  function ready() {
    document.documentElement.dataset.courseScript = "1";
    zoomPictures();
    themeToggle();
    followContents();
    document.querySelectorAll(".plotly-graph-div").forEach(f => { fitFigure(f); if (narrow()) shield(f); });
    let tries = 0;
    const typeset = () => {
      const mj = window.MathJax && window.MathJax.startup && window.MathJax.startup.promise;
      if (mj) mj.then(() => { fitFormulas(); document.documentElement.dataset.courseFitted = "1"; });
      else if (tries++ < 2000) setTimeout(typeset, 250);  // MathJax loads after this script
    };
    typeset();
    let pending = null;
    window.addEventListener("resize", () => {
      clearTimeout(pending);
      pending = setTimeout(fitFormulas, 200);
    });
  }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", ready);
  else ready();
})();

/* The course's search, on search.html (tools/book.py writes the index of sections,
   window.COURSE_SEARCH): a section is found when its own text holds the words searched
   for (the phrase, or else every word); results are ranked by how often, with the title
   counting more, and each shows its chapter and section, links to the section, and an
   excerpt with the words marked. */
(function () {
  "use strict";
  const esc = s => s.replace(/[&<>"]/g, c => ({"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;"}[c]));
  const reEsc = s => s.replace(/[.*+?^${}()|[\]\\]/g, "\\$&");

  function count(text, re) { const m = text.match(re); return m ? m.length : 0; }

  function excerpt(text, re) {
    re.lastIndex = 0;
    const m = re.exec(text);
    const at = m ? m.index : 0;
    const from = Math.max(0, at - 90), to = Math.min(text.length, at + 150);
    let s = esc(text.slice(from, to));
    if (m) s = s.replace(new RegExp(re.source, "gi"), w => "<mark>" + w + "</mark>");
    return (from > 0 ? "… " : "") + s + (to < text.length ? " …" : "");
  }

  function run() {
    const box = document.getElementById("search-results");
    const index = window.COURSE_SEARCH;
    if (!box || !index) return;
    const q = (new URLSearchParams(location.search).get("q") || "").trim();
    document.querySelectorAll("#search-documentation input[name=q], .bd-search input[name=q]")
      .forEach(input => { if (!input.value) input.value = q; });
    if (!q) return;
    // the index keeps maths as Unicode (π, θ): a word typed for a letter finds it too
    const GREEK = {pi: "π", theta: "θ", omega: "ω", phi: "φ", varphi: "φ", tau: "τ", alpha: "α",
                   beta: "β", epsilon: "ε", eps: "ε", lambda: "λ", sigma: "σ", psi: "ψ", delta: "δ"};
    const pattern = w => GREEK[w] ? `(?:${reEsc(w)}|${GREEK[w]})` : reEsc(w);
    const words = q.toLowerCase().split(/\s+/).filter(w => w.length > 0);
    const phrase = new RegExp(words.map(pattern).join("\\s+"), "gi");
    const each = words.map(w => new RegExp(pattern(w), "gi"));
    const hits = [];
    for (const e of index) {
      const text = e.x, title = e.t;
      let score = 0, re = phrase;
      const inText = count(text, phrase), inTitle = count(title, phrase);
      if (inText + inTitle > 0) score = inText + 5 * inTitle + 0.5;
      else if (words.length > 1 && each.every(r => count(text + " " + title + " " + e.c, r) > 0)) {
        score = Math.min(...each.map(r => count(text, r) + 5 * count(title, r) + 0.5 * Math.min(1, count(e.c, r))));
        re = each[0];
      }
      if (score > 0) hits.push({e, score, re});
    }
    hits.sort((a, b) => b.score - a.score);
    const h = document.createElement("h2");
    h.textContent = hits.length ? `${hits.length} section${hits.length > 1 ? "s" : ""} found for “${q}”`
                                : `No section contains “${q}”`;
    const list = document.createElement("ul");
    list.className = "search course-search";
    for (const {e, re} of hits.slice(0, 50)) {
      const li = document.createElement("li");
      li.innerHTML = `<a href="${esc(e.p)}#${esc(e.i)}">${esc(e.t)}</a>` +
        (e.t !== e.c ? ` <span class="course-search-chapter">in ${esc(e.c)}</span>` : "") +
        `<p class="context">${excerpt(e.x, re)}</p>`;
      list.appendChild(li);
    }
    box.replaceChildren(h, list);
  }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", run);
  else run();
})();
