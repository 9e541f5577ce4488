"""Plots of one recorded match on its field (matplotlib, Agg: no display needed).

Requires: the match's ``FieldGeometry`` [m] (``nubot_common.field``: every marking is drawn and the axes span
the field and its ``border``), and plain data from ``match_analysis``: ball positions [m] with the running time
[s] each covers (``BallTime``), robot ``Track``s (sim time [s], world-frame positions [m]) and the teams.
Provides: ``draw_field`` (touch, goal and halfway lines, penalty and goal areas, centre circle, corner arcs,
centre spot, penalty marks, both goals), ``plot_ball_heatmap`` (seconds of running time per cell) and
``plot_trajectories`` (one colour family per team) and ``plot_shot_map`` (every shot of each team on the half it
attacks, by outcome); each plot writes a PNG and returns its ``Figure``.
Parameters: ``bin_size`` [m] of the heat map's cells (0.5), ``teleport_step`` [m] (1.0: longer steps are not
drawn as lines), ``max_points`` per trajectory (4000).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.colors import LinearSegmentedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Arc, Circle, Rectangle

from nubot_common.commands import KickKind
from nubot_common.field import FieldGeometry
from nubot_common.naming import is_robot_name, team_colour, team_of
from nubot_match.match_analysis import Track
from nubot_match.match_shots import Shot

GRASS = "#2e7d32"
LIGHT_GRASS = "#dcedc8"


def new_figure(field: FieldGeometry) -> tuple[Figure, Axes]:
    """Return an Agg figure whose axes span the field and its border, to scale (world frame)."""
    hl, hw, b = field.half_length, field.half_width, field.border
    fig = Figure(figsize=(10, 10 * (hw + b) / (hl + b) + 0.8))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_xlim(-hl - b, hl + b)
    ax.set_ylim(-hw - b, hw + b)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (world frame)")
    ax.set_ylabel("y [m]")
    return fig, ax


def draw_field(ax: Axes, field: FieldGeometry, colour: str = "white", zorder: int = 2) -> None:
    """Draw every white marking of ``field`` (lines, areas, centre circle, corner arcs, spots) and both goals."""
    ax.add_collection(LineCollection(field.line_segments(), colors=colour, linewidths=1.5, zorder=zorder))
    for arc in field.arcs():
        ax.add_patch(Arc((arc.x, arc.y), 2 * arc.radius, 2 * arc.radius, theta1=math.degrees(arc.start),
                         theta2=math.degrees(arc.end), edgecolor=colour, linewidth=1.5, zorder=zorder))
    for x, y in field.spots():
        ax.add_patch(Circle((x, y), field.spot_diameter / 2, color=colour, zorder=zorder))
    for side in (-1, 1):
        x_back = side * (field.half_length + field.goal_depth)
        ax.add_patch(Rectangle((min(side * field.half_length, x_back), -field.goal_width / 2), field.goal_depth,
                               field.goal_width, facecolor="0.85", edgecolor="black", linewidth=2, zorder=zorder))
        for x, y in field.goal_posts(side):
            ax.add_patch(Circle((x, y), field.post_radius, color="black", zorder=zorder))


def plot_ball_heatmap(ball_xy: np.ndarray, seconds: np.ndarray, field: FieldGeometry, path: Path,
                      bin_size: float = 0.5, title: str = "Ball heat map") -> Figure:
    """Write a PNG of the running time [s] the ball spent in each ``bin_size`` cell, given its positions (N, 2)
    and the running time each covers (N,); say so plainly when there is none."""
    hl, hw, b = field.half_length, field.half_width, field.border
    x_edges = np.arange(-hl - b, hl + b + 1e-9, bin_size)
    y_edges = np.arange(-hw - b, hw + b + 1e-9, bin_size)
    xy = np.asarray(ball_xy, dtype=float).reshape(-1, 2)
    seconds = np.asarray(seconds, dtype=float)
    total = float(seconds.sum())
    fig, ax = new_figure(field)
    ax.set_facecolor(GRASS)
    if total > 0.0:
        # numpy's stubs admit only counts as bins; edges are what histogram2d documents too
        cells, _, _ = np.histogram2d(xy[:, 0], xy[:, 1], bins=(x_edges, y_edges), weights=seconds)  # type: ignore[arg-type]
        mesh = ax.pcolormesh(x_edges, y_edges, np.ma.masked_equal(cells.T, 0.0), cmap="YlOrRd", zorder=1)
        fig.colorbar(mesh, ax=ax, label=f"ball time per {bin_size:g} m cell [s]", shrink=0.8)
        ax.set_title(f"{title}: {total:.1f} s of running time covered by ball samples")
    else:
        ax.text(0.0, 0.0, "no ball position during running time", ha="center", va="center", fontsize=16,
                color="white", bbox={"facecolor": "black", "alpha": 0.6}, zorder=5)
        ax.set_title(f"{title}: no ball position during running time")
    draw_field(ax, field)
    fig.savefig(path, dpi=100, bbox_inches="tight")
    return fig


def plot_trajectories(tracks: dict[str, Track], teams: Sequence[str], field: FieldGeometry, path: Path,
                      teleport_step: float = 1.0, max_points: int = 4000,
                      title: str = "Robot trajectories") -> Figure:
    """Write a PNG of every robot's path: one colour family per team, each robot labelled at its last position."""
    fig, ax = new_figure(field)
    ax.set_facecolor(LIGHT_GRASS)
    draw_field(ax, field, colour="0.4", zorder=1)
    robots = sorted(n for n in tracks if is_robot_name(n))
    legend = []
    for team in teams:
        members = [r for r in robots if team_of(r) == team]
        colour = team_colour(team, teams)  # as in the live page and RViz
        cmap = LinearSegmentedColormap.from_list(team, ["white", colour, "black"])  # its robots from light to dark
        legend.append(f"{team} {colour}")
        for i, robot in enumerate(members):
            xy = tracks[robot].xy
            if len(xy) == 0:
                continue
            step = max(1, len(xy) // max_points)
            jumps = np.flatnonzero(np.hypot(*np.diff(xy, axis=0).T) > teleport_step) + 1
            line = np.insert(xy.astype(float), jumps, np.nan, axis=0)[::step]  # no lines across teleports
            colour = cmap(0.25 + 0.5 * (i + 1) / (len(members) + 1))
            ax.plot(line[:, 0], line[:, 1], color=colour, linewidth=1.2, alpha=0.85, label=robot, zorder=3)
            ax.plot(*xy[0], marker="o", markersize=4, color=colour, zorder=4)
            ax.plot(*xy[-1], marker="s", markersize=6, color=colour, markeredgecolor="black", zorder=4)
            ax.annotate(robot, xy[-1], xytext=(4, 4), textcoords="offset points", fontsize=8, color="black",
                        zorder=5)
    if robots:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, title="o start, \u25a0 end")
    ax.set_title(f"{title}: {', '.join(legend)}" if legend else title)
    fig.savefig(path, dpi=100, bbox_inches="tight")
    return fig


SHOT_STYLES = {"goal": ("*", "gold", 16), "saved": ("o", "tab:blue", 8), "blocked": ("X", "tab:red", 8),
               "wide": ("^", "0.5", 7), "disallowed": ("*", "0.3", 12)}  # outcome -> (marker, colour, size)


def plot_shot_map(shots: Sequence[Shot], teams: Sequence[str], field: FieldGeometry, path: Path,
                  title: str = "Shot map") -> Figure:
    """Write a PNG with one panel per team: the attacked half (the team attacking to the right whatever its end),
    each shot at the point it was kicked, marked by its outcome (a lob with a hollow marker), each goal with a line to
    where it crossed the goal line."""
    hl, hw, b = field.half_length, field.half_width, field.border
    panels = list(teams) or ["(no team)"]
    fig = Figure(figsize=(5.5 * len(panels), 5.5 * (hw + b) / (hl / 2 + b) * 0.5 + 1.5))
    FigureCanvasAgg(fig)
    for i, team in enumerate(panels):
        ax = fig.add_subplot(1, len(panels), i + 1)
        ax.set_facecolor(GRASS)
        ax.set_xlim(-0.5, hl + b)
        ax.set_ylim(-hw - b, hw + b)
        ax.set_aspect("equal")
        draw_field(ax, field)
        mine = [s for s in shots if s.team == team]
        for s in mine:
            x, y = s.origin_attacking_right()
            marker, colour, size = SHOT_STYLES[s.outcome]
            if s.outcome == "goal":
                ax.plot([x, hl], [y, s.target[1] * s.side], color="gold", linewidth=0.8, alpha=0.7, zorder=3)
            lob = s.kind == KickKind.LOB  # lobs hollow
            ax.plot(x, y, marker=marker, markersize=size, linestyle="none", zorder=4,
                    markerfacecolor="none" if lob else colour, markeredgecolor=colour if lob else "black",
                    markeredgewidth=1.2 if lob else 0.5)
        counts = {o: sum(1 for s in mine if s.outcome == o) for o in SHOT_STYLES}
        ax.set_title(f"{team}: {len(mine)} shots, " + ", ".join(f"{n} {o}" for o, n in counts.items()), fontsize=10)
        ax.set_xlabel("x [m] towards the attacked goal")
    handles = [Line2D([], [], marker=m, color=c, markersize=min(s, 10), linestyle="none", label=o)
               for o, (m, c, s) in SHOT_STYLES.items()]
    handles.append(Line2D([], [], marker="o", color="white", markeredgecolor="black", linestyle="none",
                          label="hollow: lob"))
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=len(handles), fontsize=9)
    fig.suptitle(title)
    fig.savefig(path, dpi=100, bbox_inches="tight")  # the legend hangs below the axes' labels, inside the picture
    return fig
