r"""Figure helpers for the notebooks (the only module that imports matplotlib).

The notebooks keep their figures' content in view and call these helpers only for the
boilerplate: one house style, equal 3-D axes, and drawing a body frame.
"""

import matplotlib as mpl
import matplotlib.pyplot as plt
import numpy as np

__all__ = ["FRAME_COLORS", "SLIDE_STYLE", "draw_frame", "new_3d_axes", "set_axes_equal", "use_course_style"]

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


def use_course_style():
    """One figure style for every notebook, and deterministic figure output.

    Figures are drawn for projection: at 100 dpi a figure is as many pixels as a deck
    shows it with (the slide is 1280x720), so the default 10 x 5 inches is 1000 x 500 px
    and the 16 pt tick labels are 22 px on the screen, legible from the back row. A
    figure alone on a slide under a one-line headline can be up to about 11.5 x 5.6
    inches; a 3-D figure about 6 x 5.6 (see ``new_3d_axes``). Under IPython's inline
    backend it also drops the matplotlib version from the PNG metadata, so that committed
    outputs do not change when matplotlib is upgraded.
    """
    mpl.rcParams.update(SLIDE_STYLE)
    try:
        ip = get_ipython()
    except NameError:
        return
    ip.run_line_magic("config", "InlineBackend.print_figure_kwargs = "
                      "{'bbox_inches': 'tight', 'metadata': {'Software': None}}")


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
