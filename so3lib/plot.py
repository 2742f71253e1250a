r"""Figure helpers for the notebooks (the only module that imports matplotlib).

The notebooks keep their figures' content in view and call these helpers only for the
boilerplate: one house style, equal 3-D axes, and drawing a body frame.
"""

import matplotlib as mpl
import matplotlib.pyplot as plt
import numpy as np

__all__ = ["use_course_style", "set_axes_equal", "draw_frame", "new_3d_axes", "FRAME_COLORS"]

#: Colours of the x, y and z axes of a body frame (red, green, blue, as in most tools).
FRAME_COLORS = ("tab:red", "tab:green", "tab:blue")


def use_course_style():
    """One figure style for every notebook, and deterministic figure output.

    Sets a readable size and font, light grids, and -- when running under IPython's
    inline backend -- drops the matplotlib version from the PNG metadata, so that
    committed outputs do not change when matplotlib is upgraded.
    """
    mpl.rcParams.update({
        "figure.figsize": (6.4, 4.0),
        "figure.dpi": 90,
        "axes.grid": True,
        "grid.alpha": 0.3,
        "axes.titlesize": "medium",
        "legend.fontsize": "small",
        "svg.hashsalt": "so3lib",
    })
    try:
        ip = get_ipython()  # noqa: F821 -- defined only inside IPython
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


def new_3d_axes(title, figsize=(5.0, 5.0)):
    """A figure with one 3-D axes, labelled x, y, z, and the given title."""
    fig = plt.figure(figsize=figsize)
    ax = fig.add_subplot(projection="3d")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_title(title)
    return fig, ax
