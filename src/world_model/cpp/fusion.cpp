// One robot's world model, the numbers of it (see include/world_model/fusion.hpp and world_model/world_model.py).
#include "world_model/fusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <tuple>

namespace world_model {
namespace {

constexpr double kTimeJump = 1.0;   // the clock going back by more than this: a restarted simulation [s]
constexpr double kMaxHeight = 20.0;  // a 3-D ball higher than this is a false detection [m]
constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

double wrap_angle(double angle) {
  double wrapped = std::fmod(angle + kPi, 2.0 * kPi);
  if (wrapped <= 0.0) wrapped += 2.0 * kPi;
  return wrapped - kPi;
}

double bearing(const Pose& from, double x, double y) { return wrap_angle(std::atan2(y - from.y, x - from.x) - from.theta); }

double distance(const Pose& from, double x, double y) { return std::hypot(x - from.x, y - from.y); }

// The obstacles that are somewhere: a percept that is not finite is no robot seen.
std::vector<Point> finite(const std::vector<Point>& points) {
  std::vector<Point> out;
  out.reserve(points.size());
  for (const Point& p : points) {
    if (std::isfinite(p[0]) && std::isfinite(p[1])) out.push_back(p);
  }
  return out;
}

}  // namespace

double Candidate::reach() const { return distance(observer, observation.x, observation.y); }

int choose_ball(const std::vector<Candidate>& team) {
  int chosen = -1;
  for (std::size_t i = 0; i < team.size(); ++i) {
    const Candidate& c = team[i];
    if (chosen < 0) {
      chosen = static_cast<int>(i);
      continue;
    }
    const Candidate& best = team[static_cast<std::size_t>(chosen)];
    if (std::make_tuple(c.reach(), c.age, c.agent_id) < std::make_tuple(best.reach(), best.age, best.agent_id)) {
      chosen = static_cast<int>(i);
    }
  }
  return chosen;
}

double ball_confidence(double age, int sightings, double ball_timeout, double sighting_confidence) {
  if (sightings <= 0) return 0.0;
  const double freshness = std::min(1.0, std::max(0.0, 1.0 - age / ball_timeout));
  const double support = 1.0 - std::pow(1.0 - sighting_confidence, sightings);
  return freshness * support;
}

std::optional<std::array<double, 2>> fit_velocity(const std::vector<std::array<double, 3>>& samples, int min_samples) {
  if (static_cast<int>(samples.size()) < min_samples) return std::nullopt;
  const double last = samples.back()[0];
  std::vector<double> times;
  times.reserve(samples.size());
  for (const auto& s : samples) times.push_back(s[0] - last);  // relative times keep the fit well conditioned
  if (*std::max_element(times.begin(), times.end()) - *std::min_element(times.begin(), times.end()) < 1e-6) {
    return std::nullopt;
  }
  const double n = static_cast<double>(samples.size());
  double t_sum = 0.0, x_sum = 0.0, y_sum = 0.0;
  for (const double dt : times) t_sum += dt;
  for (const auto& s : samples) x_sum += s[1];
  for (const auto& s : samples) y_sum += s[2];
  const double t_mean = t_sum / n, x_mean = x_sum / n, y_mean = y_sum / n;
  double stt = 0.0, sxt = 0.0, syt = 0.0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const double dt = times[i] - t_mean;
    stt += dt * dt;
    sxt += dt * (samples[i][1] - x_mean);
    syt += dt * (samples[i][2] - y_mean);
  }
  return std::array<double, 2>{sxt / stt, syt / stt};
}

void BallTrack::add(const Ball& ball) {
  if (!samples_.empty() && ball.stamp <= samples_.back().stamp) {
    if (ball.stamp >= samples_.back().stamp - kTimeJump) return;  // a repeat (the relay resends) or a late one
    samples_.clear();                                              // the clock went back
  }
  samples_.push_back(ball);
  fitted_ = false;
  while (samples_.front().stamp < ball.stamp - keep_) samples_.pop_front();
}

void BallTrack::clear() {
  samples_.clear();
  fitted_ = false;
}

std::optional<std::array<double, 2>> BallTrack::velocity(double window, int min_samples) const {
  if (samples_.empty()) return std::nullopt;
  if (!fitted_ || fitted_window_ != window || fitted_min_ != min_samples) {
    const double newest = samples_.back().stamp;
    std::vector<std::array<double, 3>> recent;
    for (const Ball& b : samples_) {
      if (b.stamp >= newest - window) recent.push_back({b.stamp, b.x, b.y});
    }
    fit_ = fit_velocity(recent, min_samples);
    fitted_ = true, fitted_window_ = window, fitted_min_ = min_samples;
  }
  return fit_;
}

Fusion::Fusion(const FusionParams& params)
    : p_(params),
      keep_(std::max(params.velocity_window, params.ball_timeout) + 0.1),
      clock_(-kInf),
      tracker_(params.obstacle_gate, params.obstacle_position_gain, params.obstacle_velocity_gain,
               params.obstacle_coast, params.obstacle_max_speed),
      own_track_(keep_),
      front_track_(keep_),
      rgbd_track_(keep_) {
  forget();
}

void Fusion::forget() {
  vision_ = Robot{};
  tracker_.reset();
  own_track_.clear();
  front_track_.clear();
  rgbd_track_.clear();
  ball3d_.reset();
  mates_.assign(static_cast<std::size_t>(p_.team_size), Mate{});
  mate_tracks_.assign(static_cast<std::size_t>(p_.team_size), BallTrack(keep_));
  mate_strategies_.assign(static_cast<std::size_t>(p_.team_size), std::nullopt);
  strategies_heard_ = false;
  last_ball_.reset();
}

bool Fusion::note_time(double t) {
  if (t < clock_ - kTimeJump) {
    forget();
    clock_ = t;
    return true;
  }
  clock_ = std::max(clock_, t);
  return false;
}

bool Fusion::on_field(double x, double y) const {
  return std::abs(x) <= p_.half_length + p_.border && std::abs(y) <= p_.half_width + p_.border;
}

bool Fusion::on_vision(double stamp, const Pose& pose, bool valid, const std::optional<Ball>& ball,
                       const std::vector<Point>& obstacles) {
  const bool kept = ball.has_value() && on_field(ball->x, ball->y);
  vision_ = Robot{true, stamp, pose, valid};
  tracker_.update(stamp, finite(obstacles));
  if (kept) own_track_.add(*ball);
  return kept;
}

void Fusion::on_front_ball(double stamp, double rx, double ry) {
  if (!vision_.known) return;
  const Pose& me = vision_.pose;
  const double c = std::cos(me.theta), s = std::sin(me.theta);
  const double x = me.x + (c * rx - s * ry), y = me.y + (s * rx + c * ry);
  if (on_field(x, y)) front_track_.add({stamp, x, y, 0.0, 0.0, false});
}

bool Fusion::on_ball3d(const Ball3d& ball) {
  if (!(on_field(ball.x, ball.y) && -p_.ball_radius <= ball.z && ball.z <= kMaxHeight)) return false;
  if (ball3d_.has_value() && ball.stamp <= ball3d_->stamp) return false;  // a repeat or a late one
  ball3d_ = ball;
  rgbd_track_.add({ball.stamp, ball.x, ball.y, ball.vx, ball.vy, ball.velocity_known});
  return true;
}

bool Fusion::on_teammate(double t, int agent_id, double stamp, const Pose& pose, bool valid,
                         const std::optional<Ball>& ball, const std::vector<Point>& obstacles) {
  Mate& mate = mates_[index(agent_id)];
  const double at = stamp > 0.0 ? stamp : t;
  if (mate.known && mate.stamp - kTimeJump <= at && at < mate.stamp) return false;
  std::optional<Ball> kept;
  if (ball.has_value() && on_field(ball->x, ball->y)) {
    kept = ball;
    if (kept->stamp <= 0.0) kept->stamp = at;
  }
  mate.known = true, mate.stamp = at, mate.pose = pose, mate.valid = valid;
  mate.ball = kept;
  mate.obstacles = finite(obstacles);
  if (kept.has_value()) mate_tracks_[index(agent_id)].add(*kept);
  return true;
}

void Fusion::on_teammate_strategy(int agent_id, double stamp) {
  mate_strategies_[index(agent_id)] = stamp;
  strategies_heard_ = true;
}

bool Fusion::playing(double t, int agent_id) const {
  if (agent_id == p_.agent_id || !strategies_heard_) return true;
  const auto& stamp = mate_strategies_[index(agent_id)];
  return stamp.has_value() && t - *stamp <= p_.strategy_timeout;
}

RobotState Fusion::robot(double t, int agent_id) const {
  const Robot& r = agent_id == p_.agent_id ? vision_ : mates_[index(agent_id)];
  const double stamp = r.known ? r.stamp : -kInf;
  const double age = std::max(0.0, t - stamp);
  const bool valid = r.known && r.valid && age <= p_.teammate_timeout && on_field(r.pose.x, r.pose.y) &&
                     playing(t, agent_id);
  return {valid, age};
}

const Ball3d* Fusion::flying(double t) const {
  if (!ball3d_.has_value() || t - ball3d_->stamp > p_.sensor_timeout) return nullptr;
  return ball3d_->z > p_.ball_radius + p_.air_margin ? &*ball3d_ : nullptr;
}

OwnBall Fusion::own_ball(double t) const {
  const BallTrack* track = nullptr;
  Sensor sensor = Sensor::None;
  if (flying(t) != nullptr) {
    track = &rgbd_track_, sensor = Sensor::Rgbd;
  } else {
    const std::pair<const BallTrack*, Sensor> sensors[3] = {
        {&own_track_, Sensor::Omni}, {&front_track_, Sensor::Front}, {&rgbd_track_, Sensor::Rgbd}};  // trust order
    std::vector<std::pair<const BallTrack*, Sensor>> recent;
    for (const auto& [candidate, kind] : sensors) {
      const Ball* latest = candidate->latest();
      if (latest != nullptr && t - latest->stamp <= p_.ball_timeout) recent.emplace_back(candidate, kind);
    }
    for (const auto& [candidate, kind] : recent) {
      if (t - candidate->latest()->stamp <= p_.sensor_timeout) {
        track = candidate, sensor = kind;
        break;
      }
    }
    if (track == nullptr) {
      if (recent.empty()) return {};
      track = recent[0].first, sensor = recent[0].second;  // the freshest; the first of equals
      for (const auto& [candidate, kind] : recent) {
        if (candidate->latest()->stamp > track->latest()->stamp) track = candidate, sensor = kind;
      }
    }
  }
  const Ball* latest = track->latest();
  if (latest == nullptr) return {};
  std::optional<std::array<double, 2>> velocity;
  const Ball3d* air = sensor == Sensor::Rgbd ? flying(t) : nullptr;
  if (air != nullptr && air->velocity_known) {
    velocity = std::array<double, 2>{air->vx, air->vy};  // the parabola's, fitted by the cameras
  } else {
    velocity = track->velocity(p_.velocity_window, p_.min_fit_samples);
  }
  OwnBall out;
  out.known = true;
  out.sensor = sensor;
  out.ball = {latest->stamp, latest->x, latest->y, velocity ? (*velocity)[0] : 0.0, velocity ? (*velocity)[1] : 0.0,
              velocity.has_value()};
  return out;
}

std::optional<Ball> Fusion::mate_ball(double t, int agent_id) const {
  const Mate& mate = mates_[index(agent_id)];
  if (!mate.known || !mate.ball.has_value() || t - mate.ball->stamp > p_.ball_timeout) return std::nullopt;
  return mate.ball;
}

Snapshot Fusion::snapshot(double t) {
  Snapshot out;
  const std::size_t n = static_cast<std::size_t>(p_.team_size);
  for (int aid = 1; aid <= p_.team_size; ++aid) out.robots.push_back(robot(t, aid));
  const Pose me = vision_.known ? vision_.pose : Pose{0.0, 0.0, 0.0};
  out.own = own_ball(t);
  out.mate_ball.assign(n, false);
  std::vector<Candidate> team;
  for (int aid = 1; aid <= p_.team_size; ++aid) {
    if (aid == p_.agent_id || !out.robots[index(aid)].valid) continue;
    const auto seen = mate_ball(t, aid);
    if (!seen.has_value()) continue;
    out.mate_ball[index(aid)] = true;
    team.push_back({aid, Source::Teammate, *seen, mates_[index(aid)].pose, std::max(0.0, t - seen->stamp)});
  }
  std::vector<Candidate> candidates;
  if (out.own.known) {
    candidates.push_back({p_.agent_id, Source::Own, out.own.ball, me, std::max(0.0, t - out.own.ball.stamp)});
  }
  candidates.insert(candidates.end(), team.begin(), team.end());
  const Candidate* chosen = nullptr;
  if (out.own.known) {
    chosen = &candidates[0];  // own sensors first
  } else if (const int best = choose_ball(team); best >= 0) {
    chosen = &candidates[static_cast<std::size_t>(best)];
  }
  FusedBall& ball = out.ball;
  if (chosen == nullptr) {
    const auto [x, y] = last_ball_.value_or(std::array<double, 2>{0.0, 0.0});
    ball.x = x, ball.y = y, ball.stamp = -kInf;
    ball.angle = bearing(me, x, y), ball.radius = distance(me, x, y);
  } else {
    const Ball& obs = chosen->observation;
    std::optional<std::array<double, 2>> velocity;
    if (chosen->source == Source::Own) {
      if (obs.velocity_known) velocity = std::array<double, 2>{obs.vx, obs.vy};  // fitted by own_ball
      ball.sensor = out.own.sensor;
    } else {
      velocity = mate_tracks_[index(chosen->agent_id)].velocity(p_.velocity_window, p_.min_fit_samples);
      if (!velocity.has_value() && obs.velocity_known) velocity = std::array<double, 2>{obs.vx, obs.vy};
    }
    std::set<int> agree;
    for (const Candidate& c : candidates) {
      if (std::hypot(c.observation.x - obs.x, c.observation.y - obs.y) <= p_.agreement_radius) agree.insert(c.agent_id);
    }
    last_ball_ = std::array<double, 2>{obs.x, obs.y};
    const double confidence =
        ball_confidence(chosen->age, static_cast<int>(agree.size()), p_.ball_timeout, p_.sighting_confidence);
    ball.x = obs.x, ball.y = obs.y;
    ball.vx = velocity ? (*velocity)[0] : 0.0, ball.vy = velocity ? (*velocity)[1] : 0.0;
    ball.known = true, ball.velocity_known = velocity.has_value();
    ball.confidence = confidence;
    ball.seen_by.assign(agree.begin(), agree.end());
    ball.source = chosen->source, ball.source_id = chosen->agent_id, ball.stamp = obs.stamp;
    ball.angle = bearing(me, obs.x, obs.y), ball.radius = distance(me, obs.x, obs.y);
  }
  std::vector<Point> own_obstacles;
  if (vision_.known && t - vision_.stamp <= p_.ball_timeout) tracker_.estimate(t, own_obstacles, out.velocities);
  std::vector<Seen> reported, positions;
  for (int aid = 1; aid <= p_.team_size; ++aid) {
    if (aid == p_.agent_id || !out.robots[index(aid)].valid) continue;
    const Mate& mate = mates_[index(aid)];
    for (const Point& o : mate.obstacles) reported.push_back({aid, o[0], o[1]});
    positions.push_back({aid, mate.pose.x, mate.pose.y});
  }
  out.obstacles = label_obstacles({me.x, me.y, me.theta}, p_.agent_id, own_obstacles, std::move(reported),
                                  std::move(positions), p_.teammate_radius, p_.merge_radius);
  return out;
}

OwnView Fusion::own_view(double t) const {
  OwnView out{};
  if (!vision_.known) return out;
  out.known = true;
  out.valid = robot(t, p_.agent_id).valid;
  out.ball = own_ball(t);
  out.fresh = t - vision_.stamp <= p_.ball_timeout;
  if (out.fresh) {
    std::vector<Point> velocities;
    tracker_.estimate(vision_.stamp, out.obstacles, velocities);
  }
  return out;
}

}  // namespace world_model
