// One robot's world model, the numbers of it: the compiled core of world_model.world_model.WorldModel (its docstring
// states the rules). The Python class keeps the records it was given and builds the WorldState from what this decides.
// Team frame; units SI: m, s, m/s, rad.
#pragma once

#include <array>
#include <deque>
#include <optional>
#include <vector>

#include "world_model/labels.hpp"
#include "world_model/obstacles.hpp"

namespace world_model {

// WorldModelParams and the parts of the match's world description the fusion reads.
struct FusionParams {
  int team_size, agent_id;
  double teammate_timeout, strategy_timeout, ball_timeout, velocity_window;
  int min_fit_samples;
  double teammate_radius, merge_radius, agreement_radius, sighting_confidence, sensor_timeout, air_margin;
  double obstacle_gate, obstacle_position_gain, obstacle_velocity_gain, obstacle_coast, obstacle_max_speed;
  double half_length, half_width, border;  // the field: a ball or robot beyond the lines plus border is off it
  double ball_radius;
};

struct Pose {
  double x, y, theta;
};

// A ball observation: when [s], where [m], its own per-frame velocity [m/s] if known.
struct Ball {
  double stamp, x, y, vx, vy;
  bool velocity_known;
};

// The ball in 3-D from the RGB-D cameras (z: its centre's height [m]).
struct Ball3d {
  double stamp, x, y, z, vx, vy, vz;
  bool velocity_known;
};

enum class Sensor { None = 0, Omni = 1, Front = 2, Rgbd = 3 };  // the values of nubot_common's BallSensor
enum class Source { Unknown = 0, Own = 1, Teammate = 2 };       // ... and of BallSource

// The recent ball observations of one source, duplicates and late ones dropped; the velocity fit made once per new
// observation (world_model.ball_fusion.BallTrack).
class BallTrack {
 public:
  explicit BallTrack(double keep) : keep_(keep) {}
  void add(const Ball& ball);
  void clear();
  std::size_t size() const { return samples_.size(); }
  const Ball* latest() const { return samples_.empty() ? nullptr : &samples_.back(); }
  // The least-squares velocity over the observations within window [s] of the newest; none with fewer than
  // min_samples or no spread in time.
  std::optional<std::array<double, 2>> velocity(double window, int min_samples) const;

 private:
  double keep_;
  std::deque<Ball> samples_;
  mutable bool fitted_ = false;
  mutable double fitted_window_ = 0.0;
  mutable int fitted_min_ = 0;
  mutable std::optional<std::array<double, 2>> fit_;
};

// The slope (vx, vy) [m/s] of the least-squares lines x(t), y(t) through the samples (t, x, y); none with fewer than
// min_samples or no spread in time (world_model.ball_fusion).
std::optional<std::array<double, 2>> fit_velocity(const std::vector<std::array<double, 3>>& samples, int min_samples);

// A fresh ball observation and who made it.
struct Candidate {
  int agent_id;
  Source source;
  Ball observation;
  Pose observer;
  double age;  // [s]
  double reach() const;  // observer to ball [m]: the nearer robot sees the ball better
};

// Which of the teammates' candidates to believe when this robot's own sensors have none: the one nearest to its
// ball, then the freshest, then the lower AgentID; -1 when there is none.
int choose_ball(const std::vector<Candidate>& team);

// Confidence in [0, 1]: freshness (1 now, 0 at ball_timeout) times support from the robots seeing the ball.
double ball_confidence(double age, int sightings, double ball_timeout, double sighting_confidence);

struct FusedBall {
  double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0;
  bool known = false, velocity_known = false;
  double confidence = 0.0;
  std::vector<int> seen_by;
  Source source = Source::Unknown;
  int source_id = 0;
  double stamp = 0.0;  // -inf when unknown (the Python default)
  double angle = 0.0, radius = 0.0;
  Sensor sensor = Sensor::None;
};

// This robot's own ball as the world model believes it: the newest observation of the sensor it trusts, with the
// velocity it fitted.
struct OwnBall {
  bool known = false;
  Ball ball{};
  Sensor sensor = Sensor::None;
};

struct RobotState {  // a member of the team (this robot included), by AgentID
  bool valid;
  double age;  // [s], inf when never heard of
};

struct Snapshot {
  std::vector<RobotState> robots;  // index AgentID - 1
  OwnBall own;                     // this robot's ball (team_balls of this robot)
  std::vector<bool> mate_ball;     // index AgentID - 1: whether the teammate's own fresh ball is in team_balls
  FusedBall ball;
  std::vector<Labelled> obstacles;
  std::vector<Point> velocities;  // of the first ones (this robot's own), in order
};

struct OwnView {
  bool known;  // false: nothing to share yet
  bool valid;  // this robot's validity as its teammates should take it
  OwnBall ball;
  bool fresh;  // its own perception is recent: its obstacles are shared
  std::vector<Point> obstacles;
};

class Fusion {
 public:
  explicit Fusion(const FusionParams& params);

  // The clock: true when t went back by more than a second (a restarted simulation) and everything was forgotten.
  bool note_time(double t);
  bool on_field(double x, double y) const;

  // Own percepts of the frame at stamp; returns whether its ball (if any) was kept (on the field).
  bool on_vision(double stamp, const Pose& pose, bool valid, const std::optional<Ball>& ball,
                 const std::vector<Point>& obstacles);
  // The front camera's ball at (rx, ry) from this robot; ignored before a vision frame or off the field.
  void on_front_ball(double stamp, double rx, double ry);
  // The 3-D ball; returns whether it was taken (on the field, below 20 m, newer than the last).
  bool on_ball3d(const Ball3d& ball);
  // A teammate's packet received at t; returns whether it was taken (not older than the one held). stamp: the
  // packet's (<= 0: unstamped, taken at t); its ball, re-stamped likewise, is kept only on the field.
  bool on_teammate(double t, int agent_id, double stamp, const Pose& pose, bool valid, const std::optional<Ball>& ball,
                   const std::vector<Point>& obstacles);
  // A teammate's strategy heard at stamp (its own, or the time it arrived).
  void on_teammate_strategy(int agent_id, double stamp);
  // The effective stamp and ball the last on_teammate kept for agent_id (valid only if it returned true).
  double mate_stamp(int agent_id) const { return mates_[index(agent_id)].stamp; }
  bool mate_ball_kept(int agent_id) const { return mates_[index(agent_id)].ball.has_value(); }
  double mate_ball_stamp(int agent_id) const { return mates_[index(agent_id)].ball->stamp; }

  Snapshot snapshot(double t);
  OwnView own_view(double t) const;
  bool has_vision() const { return vision_.known; }
  double vision_stamp() const { return vision_.stamp; }

 private:
  struct Robot {
    bool known = false;
    double stamp = 0.0;
    Pose pose{};
    bool valid = false;
  };
  struct Mate : Robot {
    std::optional<Ball> ball;
    std::vector<Point> obstacles;
  };

  void forget();
  std::size_t index(int agent_id) const { return static_cast<std::size_t>(agent_id - 1); }
  RobotState robot(double t, int agent_id) const;
  bool playing(double t, int agent_id) const;
  const Ball3d* flying(double t) const;
  OwnBall own_ball(double t) const;
  std::optional<Ball> mate_ball(double t, int agent_id) const;

  FusionParams p_;
  double keep_;  // history kept per ball track [s]
  double clock_;
  ObstacleTracker tracker_;
  Robot vision_;
  BallTrack own_track_, front_track_, rgbd_track_;
  std::optional<Ball3d> ball3d_;
  std::vector<Mate> mates_;
  std::vector<BallTrack> mate_tracks_;
  std::vector<std::optional<double>> mate_strategies_;  // the stamp of each teammate's latest strategy
  bool strategies_heard_ = false;
  std::optional<std::array<double, 2>> last_ball_;
};

}  // namespace world_model
