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
    whenDrawn(fig, place);
  }

  function whenDrawn(fig, then, tries = 0) {
    if (fig._fullLayout && fig.querySelector(".main-svg")) then();
    else if (tries < 100) setTimeout(() => whenDrawn(fig, then, tries + 1), 200);
  }

  /* On a narrow screen a figure's title is broken into lines that fit, in a smaller font. */
  function fitTitle(fig) {
    whenDrawn(fig, () => {
      const title = fig.layout && fig.layout.title;
      const text = title && (typeof title === "string" ? title : title.text);
      if (!text || text.includes("<br>") || !window.Plotly) return;
      const perLine = Math.max(20, Math.floor(fig.clientWidth / 8));
      const lines = [""];
      for (const word of text.split(" ")) {
        const last = lines[lines.length - 1];
        if (last && (last + " " + word).replace(/<[^>]+>/g, "").length > perLine) lines.push(word);
        else lines[lines.length - 1] = last ? last + " " + word : word;
      }
      if (lines.length < 2) return;
      const top = (fig._fullLayout.margin && fig._fullLayout.margin.t) || 60;
      window.Plotly.relayout(fig, {"title.text": lines.join("<br>"), "title.font.size": 13,
                                   "margin.t": Math.max(top, 18 * lines.length + 20)});
    });
  }

  /* A display formula wider than the column is set smaller until it fits (down to half
     its size), so that it keeps its equation number in view; one wider still scrolls. */
  function fitFormulas() {
    for (const m of document.querySelectorAll('.bd-article mjx-container[display="true"]')) {
      if (m.dataset.courseSize === undefined) m.dataset.courseSize = m.style.fontSize || "";
      m.style.fontSize = m.dataset.courseSize;
      // a numbered formula has a min-width (in em) that can exceed its column
      const avail = Math.max(1, m.parentElement ? m.parentElement.clientWidth : m.clientWidth);
      const over = Math.max(m.scrollWidth, m.offsetWidth) / avail;
      if (over > 1.01) {
        const base = parseFloat(m.dataset.courseSize) || 100;
        m.style.fontSize = (base * Math.max(0.5, 1 / over - 0.01)).toFixed(1) + "%";
      }
    }
  }

  function ready() {
    document.documentElement.dataset.courseScript = "1";
    if (narrow()) document.querySelectorAll(".plotly-graph-div").forEach(f => { fitTitle(f); shield(f); });
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
    s = s.replace(new RegExp(re.source, "gi"), w => "<mark>" + w + "</mark>");
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
    const words = q.toLowerCase().split(/\s+/).filter(w => w.length > 0);
    const phrase = new RegExp(reEsc(q.toLowerCase()).replace(/\s+/g, "\\s+"), "gi");
    const each = words.map(w => new RegExp(reEsc(w), "gi"));
    const hits = [];
    for (const e of index) {
      const text = e.x, title = e.t;
      let score = 0, re = phrase;
      const inText = count(text, phrase), inTitle = count(title, phrase);
      if (inText + inTitle > 0) score = inText + 5 * inTitle + 0.5;
      else if (words.length > 1 && each.every(r => count(text + " " + title, r) > 0)) {
        score = Math.min(...each.map(r => count(text, r) + 5 * count(title, r)));
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
