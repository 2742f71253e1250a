r"""Figure helpers for the notebooks (the only module that imports matplotlib).

The notebooks keep their figures' content in view and call these helpers only for the
boilerplate: one house style, equal 3-D axes, and drawing a body frame.

Figures a learner turns with the mouse are plotly figures shown with ``show_3d``: the
notebook keeps the figure's data (JupyterLab draws it with its plotly renderer, no kernel
and no network needed) and a small HTML part for the book and the decks, which load one
vendored copy of plotly.js instead of 4.8 MB inside every notebook.
"""

import html
import json
import re

import matplotlib as mpl
import matplotlib.pyplot as plt
import numpy as np

__all__ = ["FRAME_COLORS", "PLOTLY_COLORS", "SLIDE_STYLE", "draw_frame", "frame_traces",
           "new_3d_axes", "new_3d_figure", "set_axes_equal", "show_3d", "time_slider",
           "use_course_style"]

#: Colours of the x, y and z axes of a body frame (red, green, blue, as in most tools).
FRAME_COLORS = ("tab:red", "tab:green", "tab:blue")


#: The house style: sizes for a figure that a deck shows at its drawn size (100 px/inch).
SLIDE_STYLE = {
    "figure.figsize": (10.0, 5.0),
    "figure.dpi": 100,
    "savefig.dpi": 100,
    "font.size": 17,
    "axes.titlesize": 19,
    "axes.labelsize": 18,
    "xtick.labelsize": 16,
    "ytick.labelsize": 16,
    "legend.fontsize": 16,
    "figure.titlesize": 20,
    "lines.linewidth": 2.5,
    "lines.markersize": 8,
    "axes.linewidth": 1.2,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "svg.hashsalt": "so3lib",
}


def use_course_style(png_colours=None):
    """One figure style for every notebook, and deterministic figure output.

    Figures are drawn for projection: at 100 dpi a figure is as many pixels as a deck
    shows it with (the slide is 1280x720), so the default 10 x 5 inches is 1000 x 500 px
    and the 16 pt tick labels are 22 px on the screen, legible from the back row. A
    figure alone on a slide under a one-line headline can be up to about 11.5 x 5.6
    inches; a 3-D figure about 6 x 5.6 (see ``new_3d_axes``). Under IPython's inline
    backend it also drops the matplotlib version from the PNG metadata, so that committed
    outputs do not change when matplotlib is upgraded.

    ``png_colours=256`` stores each figure as a PNG of at most 256 colours (Pillow's
    quantizer): about a third of the bytes, and the same picture to the eye for line
    plots, for a notebook whose many figures would pass the course's 1.5 MB per file.
    """
    mpl.rcParams.update(SLIDE_STYLE)
    try:
        ip = get_ipython()
    except NameError:
        return
    ip.run_line_magic("config", "InlineBackend.print_figure_kwargs = "
                      "{'bbox_inches': 'tight', 'metadata': {'Software': None}}")
    if png_colours:
        plt.switch_backend(plt.get_backend())     # the inline backend's formatters, now
        ip.display_formatter.formatters["image/png"].for_type(
            plt.Figure, lambda fig: _quantized_png(fig, png_colours))


def _quantized_png(fig, colours):
    import io

    from PIL import Image
    drawn, stored = io.BytesIO(), io.BytesIO()
    fig.savefig(drawn, format="png", bbox_inches="tight", metadata={"Software": None})
    Image.open(drawn).convert("RGB").quantize(colours).save(stored, format="png", optimize=True)
    return stored.getvalue()


def set_axes_equal(ax, radius=None, center=(0.0, 0.0, 0.0)):
    """Give a 3-D axes equal scales, so that rotations look like rotations."""
    if radius is None:
        limits = np.array([ax.get_xlim3d(), ax.get_ylim3d(), ax.get_zlim3d()])
        center = limits.mean(axis=1)
        radius = 0.5 * (limits[:, 1] - limits[:, 0]).max()
    for setter, c in zip((ax.set_xlim3d, ax.set_ylim3d, ax.set_zlim3d), center):
        setter(c - radius, c + radius)
    ax.set_box_aspect((1, 1, 1))


def draw_frame(ax, R, origin=(0.0, 0.0, 0.0), length=1.0, label=None, alpha=1.0, lw=2.0):
    """Draw the columns of ``R`` (the body axes) as arrows from ``origin`` on a 3-D axes."""
    origin = np.asarray(origin, dtype=float)
    R = np.asarray(R, dtype=float)
    for k, color in enumerate(FRAME_COLORS):
        d = length * R[:, k]
        ax.quiver(*origin, *d, color=color, alpha=alpha, lw=lw, arrow_length_ratio=0.12)
    if label:
        ax.text(*(origin + 1.08 * length * R.sum(axis=1) / np.sqrt(3)), label)


def new_3d_axes(title, figsize=(6.0, 5.6)):
    """A figure with one 3-D axes, labelled x, y, z, and the given title."""
    fig = plt.figure(figsize=figsize)
    ax = fig.add_subplot(projection="3d")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_title(title)
    return fig, ax


# --- figures the learner turns: plotly ---------------------------------------------------

#: The body frame's colours for plotly (the same red, green, blue as ``FRAME_COLORS``).
PLOTLY_COLORS = ("#d62728", "#2ca02c", "#1f77b4")

#: Height of an interactive figure, px: with a one-line headline it fills a 1280x720 slide.
PLOTLY_HEIGHT = 560

# What the book and the decks need to draw a figure (the JupyterLab renderer brings its own).
PLOTLY_CONFIG = {"displaylogo": False, "responsive": True,
                 "modeBarButtonsToRemove": ["toImage", "resetCameraLastSave3d"]}

_NAME = re.compile(r"[a-z][a-z0-9_-]{0,62}")


def new_3d_figure(title, radius=1.2, height=PLOTLY_HEIGHT):
    """A plotly figure with one 3-D scene: equal axes from -radius to radius labelled x, y,
    z, the given title, and fonts as large as the matplotlib figures' on a projected slide
    (20 px and up: the tick labels too)."""
    import plotly.graph_objects as go

    axis = {"range": [-radius, radius], "autorange": False, "tickfont": {"size": 20}, "nticks": 5,
            "backgroundcolor": "white", "showbackground": True, "gridcolor": "#dddddd",
            "zerolinecolor": "#aaaaaa", "linecolor": "#888888"}
    fig = go.Figure()
    fig.update_layout(
        title={"text": title, "x": 0.02, "y": 0.97, "font": {"size": 20}},
        font={"size": 20},
        height=height,
        margin={"l": 0, "r": 0, "t": 48, "b": 0},
        legend={"x": 0.0, "y": 0.92, "bgcolor": "rgba(255,255,255,0.7)"},
        scene={"xaxis": {**axis, "title": {"text": "x"}},
               "yaxis": {**axis, "title": {"text": "y"}},
               "zaxis": {**axis, "title": {"text": "z"}},
               "aspectmode": "cube",
               "camera": {"eye": {"x": 1.55, "y": 1.35, "z": 0.85}}},  # whole box on a slide
        template="none",  # no plotly theme stored in the notebook: the styling is here
        paper_bgcolor="white",
    )
    return fig


def frame_traces(R, origin=(0.0, 0.0, 0.0), length=1.0, name="frame", showlegend=True, width=8):
    """Plotly traces that draw the columns of ``R`` (a body frame) as three coloured
    segments from ``origin``, named e.g. "frame x"; for an animation frame, the same list
    with a new R replaces them."""
    import plotly.graph_objects as go

    R = np.asarray(R, dtype=float)
    origin = np.asarray(origin, dtype=float)
    if R.shape != (3, 3) or origin.shape != (3,):
        raise ValueError(f"frame_traces expects a 3x3 matrix and a 3-vector origin, got shapes "
                         f"{R.shape} and {origin.shape}")
    traces = []
    for k, (axis, color) in enumerate(zip("xyz", PLOTLY_COLORS)):
        tip = origin + length * R[:, k]
        traces.append(go.Scatter3d(
            x=[origin[0], tip[0]], y=[origin[1], tip[1]], z=[origin[2], tip[2]],
            mode="lines+markers", line={"color": color, "width": width},
            marker={"size": [0, 5], "color": color},
            name=f"{name} {axis}", showlegend=showlegend, hoverinfo="name"))
    return traces


def _same(a, b):
    try:
        return bool(np.array_equal(np.asarray(a), np.asarray(b)))
    except (TypeError, ValueError):
        return a == b


def time_slider(fig, frames, labels, prefix, duration=80):
    """Animate ``fig``: ``frames`` is a list of lists of traces (each replaces the figure's
    first traces), ``labels`` the slider's value at each frame (e.g. "0.50"), ``prefix``
    what the slider moves (e.g. "τ = "). Adds a play/pause button and a slider that the
    learner drags; everything runs in the browser."""
    import plotly.graph_objects as go

    if len(frames) != len(labels) or not frames:
        raise ValueError(f"time_slider expects one label per frame, got {len(frames)} frames "
                         f"and {len(labels)} labels")
    # a frame changes only what differs from the figure's own traces (their style stays)
    first = [t.to_plotly_json() for t in frames[0]]

    def changed(trace, base):
        d = trace.to_plotly_json()
        return type(trace)({k: v for k, v in d.items()
                            if k in ("type", "x", "y", "z") or not _same(v, base.get(k))})

    fig.frames = [go.Frame(data=[changed(t, b) for t, b in zip(data, first)], name=str(label),
                           traces=list(range(len(data))))
                  for data, label in zip(frames, labels)]
    step_args = {"mode": "immediate", "frame": {"duration": 0, "redraw": True},
                 "transition": {"duration": 0}}
    fig.update_layout(
        updatemenus=[{"type": "buttons", "direction": "left", "x": 0.0, "y": 0.0,
                      "xanchor": "left", "yanchor": "top", "pad": {"t": 8, "r": 8},
                      "buttons": [
                          {"label": "▶ play", "method": "animate",
                           "args": [None, {"frame": {"duration": duration, "redraw": True},
                                           "transition": {"duration": 0},
                                           "fromcurrent": True}]},
                          {"label": "❚❚ pause", "method": "animate",
                           "args": [[None], step_args]}]}],
        sliders=[{"active": 0, "x": 0.27, "len": 0.69, "y": 0.0, "yanchor": "top",
                  "pad": {"t": 8}, "currentvalue": {"prefix": prefix, "font": {"size": 20}},
                  "steps": [{"label": str(label), "method": "animate",
                             "args": [[str(label)], step_args]} for label in labels]}],
    )
    fig.update_layout(margin={"b": 90})
    return fig


#: Coordinates in a 3-D figure are kept to this many decimals: far finer than a pixel in
#: the course's scenes (a few units across), and coarse enough that the last bit of a
#: result, which moves with the processor's BLAS and SIMD code, never shows (1e-17 and
#: -2e-17 are both 0).
DECIMALS = 6


def _round(values):
    """Floats rounded to ``DECIMALS`` places, -0.0 made 0.0, NaN and inf kept."""
    arr = np.round(np.asarray(values, dtype=float), DECIMALS) + 0.0
    return arr


def _compact(obj):
    """The figure's JSON, smaller and the same on every machine: arrays of 8 numbers or
    fewer and lists of floats as plain lists, longer float arrays in single precision, all
    rounded to ``DECIMALS`` places first."""
    import base64

    if isinstance(obj, dict):
        if set(obj) >= {"bdata", "dtype"} and obj["dtype"] == "f8":
            arr = _round(np.frombuffer(base64.b64decode(obj["bdata"]), dtype="<f8"))
            if arr.size <= 8 and np.isfinite(arr).all() and "shape" not in obj:
                return [float(v) for v in arr]
            return {**obj, "dtype": "f4",
                    "bdata": base64.b64encode(arr.astype("<f4").tobytes()).decode()}
        return {k: _compact(v) for k, v in obj.items()}
    if isinstance(obj, list):
        if obj and all(isinstance(v, float) for v in obj):
            return [float(v) for v in _round(obj)]
        return [_compact(v) for v in obj]
    return obj


def _plotly_html(fig_json, div_id, alt, height):
    """The HTML part: a div with a fixed id and the alt text as its label, drawn by the page's
    own plotly.js (window.Plotly, loaded once by the book or the deck); where there is none,
    the div says what the figure shows instead."""
    import plotly.io as pio

    body = pio.to_html(fig_json, full_html=False, include_plotlyjs=False, include_mathjax=False,
                       div_id=div_id, config=PLOTLY_CONFIG, validate=False, auto_play=False,
                       default_width="100%", default_height=f"{height}px")
    label = html.escape(alt, quote=True)
    body = body.replace(f'<div id="{div_id}" class="plotly-graph-div"',
                        f'<div id="{div_id}" class="plotly-graph-div course-plotly" role="figure" '
                        f'aria-label="{label}"', 1)
    guard = f'if (document.getElementById("{div_id}")) {{'
    if guard not in body or 'role="figure"' not in body:
        raise RuntimeError("plotly's HTML changed shape: so3lib.plot.show_3d needs updating")
    fallback = json.dumps("Interactive figure (needs plotly.js): " + alt)
    body = body.replace(guard, f'if (!window.Plotly) {{ document.getElementById("{div_id}")'
                               f'.textContent = {fallback}; }} else ' + guard, 1)
    # Drawn once the page has loaded: a 3-D scene drawn while the page is still being parsed
    # does not turn with the mouse (seen in the book and the decks).
    if body.count("<script>") != 1 or body.count("</script>") != 1:
        raise RuntimeError("plotly's HTML changed shape: so3lib.plot.show_3d needs updating")
    body = body.replace("<script>", "<script>(function () { var draw = function () {", 1)
    body = body.replace("</script>", '}; if (document.readyState === "complete") { draw(); } '
                                     'else { window.addEventListener("load", draw); } })();</script>', 1)
    return f'<div class="course-plotly-figure">{body}</div>'


def show_3d(fig, name, alt):
    """Show a plotly figure that the learner turns with the mouse, everywhere, offline.

    ``name`` (lower-case letters, digits, "-" and "_") makes the div id ``so3-<name>``, fixed
    so that re-running the notebook gives the same bytes (strict nbval); use a name once per
    notebook. ``alt`` says in words what the figure shows, for a reader who cannot see it:
    it labels the figure (aria-label on a div of role "figure", which keeps the figure's
    buttons and slider reachable) and is the text output. Put the same sentence in the
    cell's ``metadata.mystnb.image.alt``, as for any figure (tests/test_interactive.py
    checks that they agree).

    The output bundle holds ``application/vnd.plotly.v1+json`` (JupyterLab's plotly renderer,
    which needs no kernel and no network), ``text/html`` (the book and the decks, drawn by
    their one vendored plotly.js) and ``text/plain`` (the alt text). No plotly.js is stored
    in the notebook.
    """
    import plotly.io as pio
    from IPython.display import display

    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise ValueError(f"show_3d: name must be lower-case letters, digits, '-' or '_', "
                         f"starting with a letter (it becomes the div id), got {name!r}")
    if not isinstance(alt, str) or len(alt.split()) < 5:
        raise ValueError("show_3d: alt must be a sentence (five words or more) saying what the "
                         f"figure shows, got {alt!r}")
    if not hasattr(fig, "to_plotly_json"):
        raise ValueError(f"show_3d expects a plotly figure, got {type(fig).__name__}")
    if fig.layout.height is None:
        fig.update_layout(height=PLOTLY_HEIGHT)
    fig_json = _compact(json.loads(pio.to_json(fig, validate=True)))  # lists, base64 arrays
    spec = {"data": fig_json.get("data", []), "layout": fig_json.get("layout", {}),
            "config": PLOTLY_CONFIG}
    if fig_json.get("frames"):
        spec["frames"] = fig_json["frames"]
    bundle = {
        "application/vnd.plotly.v1+json": spec,
        "text/html": _plotly_html(fig_json, f"so3-{name}", alt, int(fig.layout.height)),
        "text/plain": f"Interactive 3-D figure: {alt}",
    }
    display(bundle, raw=True)
