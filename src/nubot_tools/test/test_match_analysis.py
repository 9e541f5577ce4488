"""Unit tests of match_analysis: the statistics' definitions on small hand-made records, and the plots."""

import json

import numpy as np
import pytest

from nubot_common.field import FieldGeometry
from nubot_common.world_description import WorldDescription
from nubot_match import match_analysis as ma
from nubot_tools.report import match_plots

WORLD = WorldDescription()  # 18 x 12 m, ball "football", robot radius 0.26 m
FIELD = WORLD.field
WORLD_22X14 = WorldDescription(field=FieldGeometry.msl_current())


def state(t, running, score=(0, 0), attack=(1, -1), event="", half=1, game_time=0.0):
    return ma.RefereeState(t, ("nubot", "rival"), score, attack, half, game_time, running, event)


def kick(t, robot, velocity=(0.0, 3.0, 0.0), xy=(0.0, 0.0), kind=-1):
    return ma.Kick(t, robot, kind, velocity, xy)


def test_running_intervals_follow_the_referee_and_merge_repeated_states():
    referee = [state(0.0, False), state(1.0, True), state(2.0, True), state(5.0, False), state(7.0, True)]
    assert ma.running_intervals(referee, 0.0, 10.0) == [(1.0, 5.0), (7.0, 10.0)]
    assert ma.running_intervals([], 2.0, 10.0) == [(2.0, 10.0)]
    assert ma.running_intervals([state(3.0, True)], 0.0, 10.0) == [(3.0, 10.0)]  # not running before the first


def test_overlap_counts_only_time_inside_the_intervals():
    assert ma.overlap(0.0, 10.0, [(1.0, 2.0), (5.0, 12.0)]) == pytest.approx(6.0)
    assert ma.overlap(2.0, 5.0, [(1.0, 2.0), (5.0, 12.0)]) == 0.0


def test_possession_is_running_time_per_team_of_the_last_toucher():
    touches = [ma.Touch(2.0, "nubot1"), ma.Touch(4.0, "rival2"), ma.Touch(8.0, "nubot3")]
    seconds = ma.possession(touches, [(1.0, 6.0), (7.0, 10.0)], 10.0, ["nubot", "rival"])
    # nobody 1-2; nubot 2-4; rival 4-6 and 7-8; nubot 8-10
    assert seconds == pytest.approx({"nubot": 4.0, "rival": 3.0, "nobody": 1.0})


@pytest.mark.parametrize(("velocity", "xy", "kind", "side", "shot"), [
    ((6.0, 0.0, 0.0), (5.0, 0.0), -1, 1, True),  # straight at the goal
    ((6.0, 0.78, 0.0), (3.0, 0.0), -1, 1, True),  # y = 0.78 at the line: between the posts
    ((6.0, 1.25, 0.0), (3.0, 0.0), -1, 1, True),  # y = 1.25 at the line: just wide of the post at 1.2, a shot wide
    ((6.0, 2.25, 0.0), (3.0, 0.0), -1, 1, False),  # y = 2.25 at the line: more than 1 m outside the post
    ((-6.0, 0.0, 0.0), (5.0, 0.0), -1, 1, False),  # away from the attacked goal
    ((-6.0, 0.5, 0.0), (-5.0, 0.0), -1, -1, True),  # the other team's attack
    ((6.0, 0.0, 0.0), (9.5, 0.0), -1, 1, False),  # ball already behind the goal line
    ((3.0, 5.0, 4.0), (3.0, 0.0), 1, 1, True),  # any lob towards the attacked goal
    ((3.0, 5.0, 4.0), (-8.0, 0.0), 1, 1, False),  # ... but from 17 m out: a clearance
    ((6.0, 0.0, 0.0), (-2.0, 0.0), -1, 1, False),  # straight at the goal from 11 m: no shot
    ((-3.0, 0.0, 4.0), (-8.0, 0.0), 1, 1, False),  # a lob backwards
])
def test_is_shot(velocity, xy, kind, side, shot):
    assert ma.is_shot(kick(0.0, "nubot1", velocity, xy, kind), side, FIELD) is shot


@pytest.mark.parametrize(("speed", "shot"), [(3.5, False), (3.7, True)])
def test_a_ground_kick_at_the_goal_too_slow_to_reach_its_line_is_a_pass_not_a_shot(speed, shot):
    # from x = 0.7 m straight at the goal line at 9 m: 8.3 m to roll; at 0.78 m/s^2 a ball needs 3.6 m/s for that
    assert ma.is_shot(kick(0.0, "nubot1", (speed, 0.0, 0.0), (0.7, 0.0)), 1, FIELD, decel=0.78) is shot
    log = ma.MatchLog(kicks=[kick(1.0, "nubot1", (speed, 0.0, 0.0), (0.7, 0.0))], start=0.0, end=2.0)
    summary = ma.analyse(log, WORLD)
    assert summary.shot_counts() == {"nubot": int(shot)}
    assert summary.pass_counts()["nubot"]["tried"] == int(not shot)


def test_shots_are_judged_on_the_world_s_field():
    # from x = 9.5 m straight at +x: behind the goal line of the 18 m field, 1.5 m before that of the 22 m field
    log = ma.MatchLog(kicks=[kick(1.0, "nubot1", (6.0, 0.0, 0.0), (9.5, 0.0))], start=0.0, end=2.0)
    assert ma.analyse(log, WORLD).shot_counts() == {"nubot": 0}
    assert ma.analyse(log, WORLD_22X14).shot_counts() == {"nubot": 1}
    assert ma.analyse(log, WORLD_22X14).to_json()["field"] == {"length_m": 22.0, "width_m": 14.0,
                                                                 "goal_width_m": 2.4}


def classify(kicks, touches=(), goals=(), referee=(), end=20.0):
    log = ma.MatchLog(kicks=list(kicks), touches=list(touches), goals=list(goals), referee=list(referee),
                      start=0.0, end=end)
    intervals = ma.running_intervals(log.referee, 0.0, end)
    return ma.classify_kicks(log, intervals, {"nubot": 1, "rival": -1}, FIELD)


def test_pass_to_a_teammate_is_completed_and_to_an_opponent_intercepted():
    out = classify([kick(1.0, "nubot2"), kick(5.0, "nubot3")],
                   [ma.Touch(0.5, "nubot2"), ma.Touch(2.0, "nubot3"), ma.Touch(6.0, "rival1")])
    assert [(k.pass_outcome, k.receiver) for k in out] == [("completed", "nubot3"), ("intercepted", "rival1")]
    assert not any(k.shot for k in out)


def test_kicks_count_as_touches_of_the_kicker():
    out = classify([kick(1.0, "nubot2"), kick(3.0, "nubot4")])  # no BallTouch at all
    assert out[0].pass_outcome == "completed" and out[0].receiver == "nubot4"
    assert out[1].pass_outcome == "unresolved"


def test_pass_is_lost_when_play_stops_a_goal_falls_or_the_kicker_kicks_again():
    referee = [state(0.0, True), state(2.0, False), state(3.0, True)]
    stopped = classify([kick(1.0, "nubot2")], [ma.Touch(4.0, "nubot3")], referee=referee)
    goal = classify([kick(1.0, "nubot2")], [ma.Touch(4.0, "nubot3")], goals=[ma.Goal(2.0, -1, (-9.1, 0.0), "")])
    again = classify([kick(1.0, "nubot2"), kick(2.0, "nubot2")], [ma.Touch(4.0, "nubot3")])
    assert stopped[0].pass_outcome == goal[0].pass_outcome == again[0].pass_outcome == "lost"
    assert again[1].pass_outcome == "completed"


def test_kicks_outside_play_are_neither_passes_nor_shots():
    out = classify([kick(1.0, "nubot2", velocity=(6.0, 0.0, 0.0))], referee=[state(0.0, False)])
    assert not out[0].in_play and not out[0].shot and out[0].pass_outcome == ""


def test_shots_use_the_attack_in_force_at_the_kick():
    referee = [state(0.0, True, attack=(1, -1)), state(10.0, True, attack=(-1, 1), half=2)]
    first, second = classify([kick(5.0, "nubot1", (6.0, 0.0, 0.0), (5.0, 0.0)),
                              kick(15.0, "nubot1", (6.0, 0.0, 0.0), (5.0, 0.0))], referee=referee)
    assert first.shot and not second.shot


def test_distance_run_leaves_out_teleports():
    xy = np.array([[0.0, 0.0], [0.3, 0.4], [0.6, 0.8], [5.0, 5.0], [5.0, 5.5]])  # 0.5 + 0.5 + jump + 0.5
    assert ma.distance_run(ma.Track("nubot1", np.arange(5.0), xy)) == pytest.approx(1.5)
    assert ma.distance_run(ma.Track("nubot1", np.arange(5.0), xy), teleport_step=10.0) > 7.0
    assert ma.distance_run(ma.Track("nubot1", np.zeros(1), xy[:1])) == 0.0


def test_referee_events_are_the_changes_of_last_event():
    referee = [state(0.0, False), state(1.0, True, event="kick-off"), state(2.0, True, event="kick-off"),
               state(3.0, False, event="throw-in"), state(4.0, True, event="kick-off")]
    assert ma.referee_events(referee) == [(1.0, "kick-off"), (3.0, "throw-in"), (4.0, "kick-off")]


def test_goals_are_credited_to_the_attacking_team_and_own_goals_marked():
    referee = [state(0.0, True), state(10.0, True, attack=(-1, 1), half=2)]
    log = ma.MatchLog(goals=[ma.Goal(5.0, 1, (9.1, 0.0), "nubot2"), ma.Goal(12.0, 1, (9.1, 0.0), "nubot3")],
                      referee=referee, start=0.0, end=20.0)
    goals, warnings = ma.credit_goals(log, {"nubot": 1, "rival": -1})
    assert [(g.team, g.own_goal, g.half, g.game_time) for g in goals] == [("nubot", False, 1, 5.0),
                                                                         ("rival", True, 2, 2.0)]
    assert warnings == []


def test_a_goal_while_play_is_stopped_is_listed_apart_and_not_counted():
    log = ma.MatchLog(goals=[ma.Goal(5.0, -1, (-9.1, 0.0), "nubot4"), ma.Goal(12.0, 1, (9.1, 0.0), "nubot2"),
                             ma.Goal(15.1, 1, (9.1, 0.0), "nubot3")],
                      referee=[state(0.0, True), state(4.0, False), state(8.0, True, score=(1, 0)),
                               state(15.0, False, score=(2, 0))],  # the referee saw the last goal 0.1 s first
                      start=0.0, end=20.0)
    summary = ma.analyse(log, WORLD)
    assert summary.score == {"nubot": 2, "rival": 0} and summary.score_agrees
    assert [g.goal.t for g in summary.goals_outside_play] == [5.0]
    assert summary.to_json()["goals_outside_play"] == [{"t": 5.0, "side": -1, "last_touch": "nubot4"}]


def test_a_goal_just_after_full_time_is_not_counted_as_the_referee_did_not():
    log = ma.MatchLog(goals=[ma.Goal(20.035, 1, (9.1, 0.0), "nubot2")],
                      referee=[state(0.0, True), state(20.0, False, event="end of the half")],  # full time, score 0-0
                      start=0.0, end=25.0)
    summary = ma.analyse(log, WORLD)
    assert summary.score == {"nubot": 0, "rival": 0} and summary.score_agrees
    assert [g.goal.t for g in summary.goals_outside_play] == [20.035]


def test_analyse_reports_a_referee_score_that_differs():
    log = ma.MatchLog(goals=[ma.Goal(5.0, 1, (9.1, 0.0), "nubot2")],
                      referee=[state(0.0, True), state(6.0, True, score=(0, 0))], start=0.0, end=10.0)
    summary = ma.analyse(log, WORLD)
    assert summary.score == {"nubot": 1, "rival": 0}
    assert summary.referee_score == {"nubot": 0, "rival": 0}
    assert not summary.score_agrees
    assert summary.to_json()["score_agrees"] is False


def test_analyse_without_referee_uses_the_default_attack_and_all_time():
    log = ma.MatchLog(goals=[ma.Goal(5.0, 1, (9.1, 0.0), "rival2")], touches=[ma.Touch(0.0, "rival2")],
                      start=0.0, end=10.0)
    summary = ma.analyse(log, WORLD, default_attack=("rival", 1))
    assert summary.score == {"rival": 1}
    assert summary.running_time == 10.0
    assert summary.possession_share() == {"rival": 1.0, "nobody": 0.0}
    assert "no referee state recorded" in summary.warnings[0]


def test_summary_json_has_every_section_and_serialises():
    log = ma.MatchLog(tracks={"nubot1": ma.Track("nubot1", np.array([0.0, 1.0]), np.array([[0.0, 0.0], [0.0, 1.0]]))},
                      kicks=[kick(1.0, "nubot1")], referee=[state(0.0, True)], start=0.0, end=2.0)
    report = ma.analyse(log, WORLD).to_json()
    assert {"teams", "score", "score_from_referee", "goals", "possession", "passes", "shots", "referee_events",
            "distance_run_m", "definitions", "kicks", "field", "ball_time_in_play_s"} <= set(report)
    assert report["passes"]["nubot"] == {"tried": 1, "completed": 0, "failed": 1, "intercepted": 0, "lost": 0,
                                         "unresolved": 1}
    assert report["distance_run_m"] == {"nubot1": 1.0}
    json.dumps(report)


def test_sample_times_shared_by_a_run_are_spread_up_to_the_next_time():
    # /clock at 10 Hz, samples at 50 Hz: runs of five samples share a time
    t = np.repeat([0.0, 0.1, 0.2, 0.3], 5)
    assert ma.spread_repeated_times(t) == pytest.approx(np.arange(20) * 0.02)  # the last run: one typical step
    assert ma.spread_repeated_times(np.array([1.0, 1.0, 2.0, 3.0])) == pytest.approx([1.0, 1.5, 2.0, 3.0])
    distinct = np.array([0.0, 0.01, 0.03])
    assert ma.spread_repeated_times(distinct).tolist() == distinct.tolist()
    assert ma.spread_repeated_times(np.array([5.0, 5.0])).tolist() == [5.0, 5.0]  # nothing to spread over


def test_each_sample_covers_the_time_to_the_next_and_the_last_the_median_step():
    assert ma.sample_durations(np.array([0.0, 0.1, 0.2, 0.5])) == pytest.approx([0.1, 0.1, 0.3, 0.1])
    assert ma.sample_durations(np.array([3.0])).tolist() == [0.0]


def test_ball_time_in_play_is_the_running_time_the_ball_samples_cover():
    t = np.arange(0, 1001) / 100.0  # 0-10 s
    ball = ma.Track("football", t, np.column_stack([t, np.zeros(len(t))]))
    inside = ma.ball_time_in_play(ball, [(1.0, 4.0), (6.005, 9.005)])
    assert inside.total == pytest.approx(6.0)
    assert inside.xy[:, 0].min() == pytest.approx(1.0) and inside.xy[:, 0].max() == pytest.approx(9.0)
    assert inside.seconds[inside.xy[:, 0] == 6.0] == pytest.approx([0.005])  # half its step is running time
    assert ma.ball_time_in_play(None, [(0.0, 10.0)]).total == 0.0


def test_analyse_reports_the_ball_time_in_play_and_warns_when_there_is_none():
    t = np.arange(0, 501) / 50.0
    ball = ma.Track("football", t, np.zeros((len(t), 2)))
    referee = [state(0.0, False), state(2.0, True), state(6.0, False)]
    summary = ma.analyse(ma.MatchLog(tracks={"football": ball}, referee=referee, start=0.0, end=10.0), WORLD)
    assert summary.to_json()["ball_time_in_play_s"] == 4.0
    assert summary.warnings == []
    early = ma.Track("football", t[t < 2.0], np.zeros((100, 2)))  # the ball track ends before play starts
    quiet = ma.analyse(ma.MatchLog(tracks={"football": early}, referee=referee, start=0.0, end=10.0), WORLD)
    assert quiet.to_json()["ball_time_in_play_s"] == 0.0
    assert quiet.warnings == ["no ball (football) position during running time (no sample falls in running time): "
                              "the heat map is empty"]


def test_the_ball_is_the_model_the_world_names():
    t = np.arange(0, 101) / 10.0
    tracks = {"ball": ma.Track("ball", t, np.zeros((len(t), 2))),
              "football": ma.Track("football", t, np.full((len(t), 2), 5.0))}  # some other model
    log = ma.MatchLog(tracks=tracks, start=0.0, end=10.0)
    assert ma.analyse(log, WorldDescription(ball_name="ball")).ball_in_play.xy[:, 0].max() == 0.0
    warnings = ma.analyse(log, WorldDescription(ball_name="orange")).warnings
    assert "no ball (orange) position during running time (no model of that name was recorded)" in warnings[-1]


def trajectories(t):
    return {"nubot1": ma.Track("nubot1", t, np.column_stack([t - 5.0, np.sin(t)])),
            "nubot2": ma.Track("nubot2", t, np.column_stack([-t, np.cos(t)])),
            "rival1": ma.Track("rival1", t, np.column_stack([np.where(t < 5, t, t - 4.0), -np.sin(t)])),
            "football": ma.Track("football", t, np.column_stack([t - 2.0, t / 3.0]))}


def test_plots_write_pngs_and_say_what_the_heat_map_covers(tmp_path):
    t = np.linspace(0.0, 10.0, 101)
    tracks = trajectories(t)
    heat = match_plots.plot_ball_heatmap(tracks["football"].xy, np.full(len(t), 0.1), FIELD, tmp_path / "heat.png")
    empty = match_plots.plot_ball_heatmap(np.zeros((0, 2)), np.zeros(0), FIELD, tmp_path / "empty.png")
    match_plots.plot_trajectories(tracks, ["nubot", "rival"], FIELD, tmp_path / "traj.png")
    for name in ("heat.png", "empty.png", "traj.png"):
        data = (tmp_path / name).read_bytes()
        assert data.startswith(b"\x89PNG") and len(data) > 10_000
    assert heat.axes[0].get_title() == "Ball heat map: 10.1 s of running time covered by ball samples"
    assert heat.axes[1].get_ylabel() == "ball time per 0.5 m cell [s]"  # the colour bar
    assert empty.axes[0].get_title() == "Ball heat map: no ball position during running time"
    assert [text.get_text() for text in empty.axes[0].texts] == ["no ball position during running time"]


def test_heat_map_cells_hold_seconds(tmp_path):
    xy = np.array([[0.1, 0.1], [0.2, 0.2], [3.1, 0.1]])  # two samples in one cell, one in another
    fig = match_plots.plot_ball_heatmap(xy, np.array([0.5, 0.25, 2.0]), FIELD, tmp_path / "heat.png")
    cells = fig.axes[0].collections[0].get_array()
    assert sorted(cells.compressed().tolist()) == [0.75, 2.0]


def test_plots_span_the_field_and_its_border(tmp_path):
    fig = match_plots.plot_trajectories(trajectories(np.linspace(0.0, 10.0, 11)), ["nubot", "rival"],
                                        WORLD_22X14.field, tmp_path / "traj.png")
    assert (fig.axes[0].get_xlim(), fig.axes[0].get_ylim()) == ((-12.0, 12.0), (-8.0, 8.0))


def test_draw_field_draws_every_marking():
    from matplotlib.patches import Arc, Circle, Rectangle

    field = WORLD_22X14.field
    _, ax = match_plots.new_figure(field)
    match_plots.draw_field(ax, field)
    segments = {tuple(map(tuple, np.round(seg, 6))) for seg in ax.collections[0].get_segments()}
    assert segments == {tuple(map(tuple, np.round(seg, 6))) for seg in field.line_segments()}
    arcs = sorted((p.center, p.width / 2) for p in ax.patches if isinstance(p, Arc))
    assert arcs == sorted(((a.x, a.y), a.radius) for a in field.arcs())
    spots = sorted(p.center for p in ax.patches if isinstance(p, Circle) and p.radius == field.spot_diameter / 2)
    assert spots == sorted(field.spots())
    goals = sorted(p.get_x() for p in ax.patches if isinstance(p, Rectangle))
    assert goals == [-11.6, 11.0]


# --- time to reach the ball: ball still at the origin, 30 Hz samples over 0-20 s --------------------------------

T30 = np.arange(0, 601) / 30.0


def track(name, x, y=0.0, t=T30):
    return ma.Track(name, t, np.column_stack([np.broadcast_to(x, t.shape), np.broadcast_to(y, t.shape)]))


def free_at_10_reached_at_12_5(t=T30):
    """nubot1 holds the ball until 10 s; nubot3 passes 0.8 m from it at 11 s; rival2 reaches it at 12.5 s."""
    return [track("football", 0.0),
            track("nubot1", np.where(T30 < 10.0, 0.3, 3.0)),
            track("nubot3", np.interp(T30, [0.0, 10.8, 11.0, 11.2], [-5.0, -5.0, -0.8, -5.0])),
            track("rival2", 0.0, np.maximum(0.3, 0.3 + 5.0 * (12.5 - t)), t=t)]  # 0.47 m one sample before


def reach_summary(tracks, referee=(), end=20.0):
    log = ma.MatchLog(tracks={tr.name: tr for tr in tracks}, referee=list(referee), start=0.0, end=end)
    return ma.analyse(log, WORLD)


def test_free_ball_reached_by_a_rival_is_one_episode_credited_to_rival():
    s = reach_summary(free_at_10_reached_at_12_5())
    assert [(r.t_free, r.t_reached, r.robot, r.team) for r in s.ball_reaches] == [(10.0, 12.5, "rival2", "rival")]
    report = s.to_json()["ball_reach"]
    assert (report["episodes"], report["median_s"], report["mean_s"], report["durations_s"]) == (1, 2.5, 2.5, [2.5])
    assert report["per_team"] == {"nubot": {"episodes": 0, "median_s": None, "mean_s": None},
                                  "rival": {"episodes": 1, "median_s": 2.5, "mean_s": 2.5}}
    assert report["dropped"] == 0
    json.dumps(report)


def test_episode_cut_by_a_stoppage_or_the_end_of_the_recording_is_dropped():
    stopped = reach_summary(free_at_10_reached_at_12_5(), referee=[state(0.0, True), state(12.0, False),
                                                                   state(14.0, True)])
    assert stopped.ball_reaches == [] and stopped.ball_reaches_dropped == 1  # rival2 reached it while stopped
    cut = [ma.Track(tr.name, tr.t[tr.t <= 12.0], tr.xy[tr.t <= 12.0]) for tr in free_at_10_reached_at_12_5()]
    ended = reach_summary(cut, end=12.0)
    assert ended.ball_reaches == [] and ended.ball_reaches_dropped == 1
    assert ended.to_json()["ball_reach"]["median_s"] is None


def test_episode_starting_in_a_stoppage_counts_from_the_restart():
    s = reach_summary(free_at_10_reached_at_12_5(), referee=[state(0.0, True), state(9.0, False), state(11.5, True)])
    assert [(r.t_free, r.t_reached) for r in s.ball_reaches] == [(11.5, 12.5)]


def test_ball_reach_statistics_per_team():
    nubot = np.where((T30 < 2.0) | ((T30 >= 3.0) & (T30 < 5.0)) | (T30 >= 12.0), 0.3, 3.0)
    rival = np.where((T30 >= 7.0) & (T30 < 8.0), -0.3, -3.0)
    s = reach_summary([track("football", 0.0), track("nubot1", nubot), track("rival1", rival)])
    assert [(r.t_free, r.t_reached, r.robot) for r in s.ball_reaches] == [
        (2.0, 3.0, "nubot1"), (5.0, 7.0, "rival1"), (8.0, 12.0, "nubot1")]
    report = s.to_json()["ball_reach"]
    assert (report["episodes"], report["median_s"], report["mean_s"]) == (3, 2.0, 2.333)
    assert report["per_team"] == {"nubot": {"episodes": 2, "median_s": 2.5, "mean_s": 2.5},
                                  "rival": {"episodes": 1, "median_s": 2.0, "mean_s": 2.0}}
    assert report["durations_s"] == [1.0, 2.0, 4.0]


def test_ball_reach_leaves_out_robots_before_their_track_starts():
    # rival2 is first seen at 12.5 s (25 Hz) next to the ball: holding that position earlier would hide the free ball
    late = 12.5 + np.arange(0, 188) / 25.0
    tracks = [*free_at_10_reached_at_12_5()[:3], track("rival2", 0.0, 0.3, t=late)]
    s = reach_summary(tracks)
    assert [(r.t_free, r.t_reached, r.robot) for r in s.ball_reaches] == [(10.0, 12.5, "rival2")]


def test_ball_reach_needs_a_ball_and_a_smaller_reach_distance():
    assert ma.ball_reaches({"nubot1": track("nubot1", 3.0)}, [(0.0, 20.0)]) == ([], 0)
    with pytest.raises(ValueError, match="reach distance 1.0 m must be below the free distance 1.0 m"):
        ma.ball_reaches({}, [(0.0, 20.0)], free_distance=1.0, reach_distance=1.0)


def test_a_kick_aimed_at_a_teammate_is_a_pass_and_one_at_nobody_a_clearance():
    t = np.array([0.0, 20.0])
    tracks = {"nubot3": ma.Track("nubot3", t, np.array([[3.0, 3.2], [3.0, 3.2]])),
              "nubot2": ma.Track("nubot2", t, np.array([[0.0, 0.0], [0.0, 0.0]]))}
    at_mate = kick(1.0, "nubot2", (3.0, 3.0), (0.0, 0.0))  # 0.14 m off nubot3
    upfield = kick(3.0, "nubot2", (-1.0, 6.0), (0.0, 0.0))  # towards the side line, nobody there
    short = kick(5.0, "nubot2", (1.1, 1.1), (0.0, 0.0))  # rolls 1.6 m: well short of nubot3 4.4 m away
    log = ma.MatchLog(tracks=tracks, kicks=[at_mate, upfield, short], start=0.0, end=20.0)
    summary = ma.analyse(log, WORLD)
    assert [(k.clearance, k.pass_outcome != "") for k in summary.kicks] == [(False, True), (True, False), (True, False)]
    assert summary.to_json()["clearances"] == {"nubot": 2}
    assert ma.aimed_at_teammate(at_mate, {}, 0.78) is None, "no track: a pass as before"


def test_resampling_reads_only_the_piece_around_its_times_and_gets_what_the_whole_track_gives():
    rng = np.random.default_rng(5)
    t = np.cumsum(rng.uniform(0.005, 0.02, 5000))
    track = ma.Track("nubot1", t, rng.normal(size=(5000, 2)))
    for times in (np.sort(rng.uniform(t[100], t[300], 50)), rng.uniform(t[0] - 1, t[-1] + 1, 50),  # unsorted
                  t[1000:1200].copy(), np.array([t[0]]), np.array([t[-1]]), np.array([t[42], t[42]])):
        whole = np.full((len(times), 2), np.nan)
        covered = (times >= t[0]) & (times <= t[-1])
        for axis in (0, 1):
            whole[covered, axis] = np.interp(times[covered], t, track.xy[:, axis])
        np.testing.assert_array_equal(ma.resample([track], times)[:, 0], whole)
    piece = track.around(t[1000] + 1e-4, t[1199] - 1e-4)
    assert piece.t[0] == t[1000] and piece.t[-1] == t[1199] and len(piece.t) == 200
    assert len(track.around(t[1000], t[1199]).t) == 200  # a time on a sample needs no neighbour
    assert len(track.around(t[-1] + 5, t[-1] + 6).t) == 1 and len(track.around(t[0] - 6, t[0] - 5).t) == 1
    assert ma.resample([track], np.zeros(0)).shape == (0, 1, 2)
