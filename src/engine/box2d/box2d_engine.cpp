// The charge on the Box2D 2.4 library: disks are dynamic circles, the mill a kinematic body
// whose inner boundary is one loop chain. Everything in here is in Box2D's scaled units;
// conversion to SI happens when state and contacts leave this file.
//
// Scaling. Box2D 2.4's tolerances are compile-time lengths tuned for bodies 0.1-10 units
// across (5 mm slop, 0.1 m AABB margin, 1 m/s restitution threshold). We scale lengths so the
// mean disk is about 0.6 units across (a 1000-disk probe ran 3.5x faster so than at metre
// scale) and keep time in seconds: a length L metres is L * units_per_m units, a velocity
// scales the same way, masses stay in kg (density is set per scaled area).
//
// Continuous collision is off: against a kinematic mill it sends every wall contact through
// the time-of-impact pass (seconds per step at 10k disks). Without it disks can tunnel at
// large time steps, so every step checks for escaped disks and reports them.
#include "common/units.hpp"
#include "engine/box2d/box2d_engine.hpp"

#include <box2d/box2d.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "geometry/simplify.hpp"

namespace millwear {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

bool finite(Vec2 v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// The energy each ongoing disk-disk collision has dissipated so far, by its Box2D contact:
// open addressing with linear probing in one array kept at its high-water size, so adding
// a step's loss (every acting contact, every step) and closing an event never allocate
// once the table has grown to the charge's collisions. Erased slots keep a tombstone until
// the next growth or clear.
class EventEnergies {
 public:
  // Adds energy_J to contact c's event, opening it if it is new.
  void add(const b2Contact* c, double energy_J) {
    if (2 * (used_ + 1) > slots_.size()) grow();
    std::size_t i = home(c), free = kNone;
    for (;; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.key == c) { s.energy_J += energy_J; return; }
      if (s.key == tombstone() && free == kNone) free = i;
      if (s.key == nullptr) break;
    }
    if (free == kNone) { free = i; ++used_; }
    slots_[free] = {c, energy_J};
  }
  // Closes contact c's event: its energy, or false when it had none.
  bool take(const b2Contact* c, double& energy_J) {
    if (slots_.empty()) return false;
    for (std::size_t i = home(c);; i = (i + 1) & mask_) {
      Slot& s = slots_[i];
      if (s.key == nullptr) return false;
      if (s.key == c) {
        energy_J = s.energy_J;
        s.key = tombstone();
        return true;
      }
    }
  }
  void clear() {
    std::fill(slots_.begin(), slots_.end(), Slot{});
    used_ = 0;
  }

 private:
  struct Slot {
    const b2Contact* key = nullptr;
    double energy_J = 0.0;
  };
  static constexpr std::size_t kNone = ~std::size_t{0};
  static const b2Contact* tombstone() { return reinterpret_cast<const b2Contact*>(alignof(b2Contact)); }
  // Fibonacci hashing: the product's high bits, which every bit of the address moves.
  std::size_t home(const b2Contact* c) const {
    return static_cast<std::size_t>((static_cast<std::uint64_t>(reinterpret_cast<std::uintptr_t>(c)) *
                                     0x9E3779B97F4A7C15ull) >> shift_);
  }
  // Twice the slots, or the same number without the tombstones when they are most of it.
  void grow() {
    std::size_t live = 0;
    for (const Slot& s : slots_) live += s.key != nullptr && s.key != tombstone();
    std::vector<Slot> old;
    old.swap(slots_);
    std::size_t size = std::max<std::size_t>(64, old.size());
    while (4 * (live + 1) > size) size *= 2;
    slots_.assign(size, Slot{});
    mask_ = size - 1;
    shift_ = 64;
    for (std::size_t s = size; s > 1; s >>= 1) --shift_;
    used_ = 0;
    for (const Slot& s : old)
      if (s.key != nullptr && s.key != tombstone()) add(s.key, s.energy_J);
  }
  std::vector<Slot> slots_;
  std::size_t mask_ = 0, used_ = 0;  // used_: slots live or tombstoned
  int shift_ = 64;                   // 64 - log2(slots)
};

class Box2DEngine;

// Contact begin/end events: per contact *event*, never per step.
class Listener final : public b2ContactListener {
 public:
  explicit Listener(Box2DEngine* owner) : owner_(owner) {}
  void BeginContact(b2Contact* contact) override;
  void EndContact(b2Contact* contact) override;

 private:
  Box2DEngine* owner_;
};

class Box2DEngine final : public Engine {
 public:
  Box2DEngine(const Scene& scene, const MillGeometry& mill, const ChargeState& initial,
              const AccountingOptions& opts);
  ~Box2DEngine() override {
    world_->SetContactListener(nullptr);
  }

  void set_liner(const MillGeometry& mill) override;
  void set_mill_speed(double omega_rad_s) override;
  void step(int n) override;
  const ChargeState& state() const override { return state_; }
  double time_step_s() const override { return dt_; }
  const char* backend_name() const override { return "box2d"; }

  void on_begin(b2Contact* c);
  void on_end(b2Contact* c);

 private:
  void step_once();
  void read_back();
  void account_contacts();
  void check_inside_liner();
  void remove_disk(std::size_t i, const std::string& why);
  int fine_edge_of(int chain_child, Vec2 point_world) const;
  int disk_of(const b2Body* b) const {
    return static_cast<int>(const_cast<b2Body*>(b)->GetUserData().pointer) - 1;  // 0: the mill
  }

  double units_per_m_ = 1.0;
  double dt_ = 0.0;  // the scene's solver.time_step
  int velocity_iterations_ = 8;
  int position_iterations_ = 3;
  double radius_m_ = 0.0;
  double band_m_ = 0.0;
  double escape_radius_m_ = 0.0;
  double shape_band_m_ = 0.0;

  std::unique_ptr<b2World> world_;
  Listener listener_{this};
  b2Body* mill_body_ = nullptr;
  b2Fixture* liner_ = nullptr;
  std::vector<b2Body*> bodies_;
  ChargeState state_;
  MillGeometry mill_;
  std::vector<std::uint8_t> edge_is_shell_;
  // The chain is a Douglas-Peucker copy of the fine liner (few long edges keep Box2D's
  // broad phase cheap: every kinematic edge proxy moves every step). Coarse edge k spans
  // fine edges coarse_start_[k] .. +coarse_count_[k]; fine_t_ holds, from offset k, the
  // projection parameter on the coarse edge of each interior fine vertex.
  int chain_count_ = 0;
  double liner_tolerance_m_ = 0.0;
  std::vector<int> coarse_start_, coarse_count_, fine_t_offset_;
  std::vector<double> fine_t_;
  // Velocities at the end of the last step: the "before" of the energy accounting
  // (soft-solver.md, "Accounting").
  std::vector<Vec2> velocity_before_;
  std::vector<double> spin_before_;
  std::vector<Vec2> position_before_;
  std::vector<float> friction_liner_, restitution_liner_;
  EventEnergies event_energy_J_;
};

void Listener::BeginContact(b2Contact* contact) { owner_->on_begin(contact); }
void Listener::EndContact(b2Contact* contact) { owner_->on_end(contact); }

Box2DEngine::Box2DEngine(const Scene& scene, const MillGeometry& mill, const ChargeState& initial,
                         const AccountingOptions& opts)
    : state_(initial) {
  accounting_.options = opts;
  dt_ = scene.solver.time_step_s;
  velocity_iterations_ = scene.solver.velocity_iterations;
  position_iterations_ = scene.solver.position_iterations;
  radius_m_ = mill.radius_m;

  double mean_d = 0.0;
  for (double r : state_.radius_m) mean_d += 2.0 * r;
  mean_d = state_.size() ? mean_d / static_cast<double>(state_.size()) : 0.1 * radius_m_;
  units_per_m_ = 0.6 / mean_d;

  world_ = std::make_unique<b2World>(b2Vec2(0.0f, static_cast<float>(-kGravity * units_per_m_)));
  world_->SetAllowSleeping(false);  // the turning mill keeps everything awake anyway
  world_->SetContinuousPhysics(false);
  world_->SetContactListener(&listener_);

  b2BodyDef mill_def;
  mill_def.type = b2_kinematicBody;
  mill_def.userData.pointer = 0;
  // A charge carried over from an earlier engine keeps its mill angle and speed.
  mill_def.angle = static_cast<float>(std::remainder(state_.mill_angle_rad, 2.0 * kPi));
  mill_def.angularVelocity = static_cast<float>(state_.mill_speed_rad_s);
  mill_body_ = world_->CreateBody(&mill_def);

  for (const auto& sp : scene.charge.species) {
    friction_liner_.push_back(static_cast<float>(sp.friction_liner));
    restitution_liner_.push_back(static_cast<float>(sp.restitution_liner));
  }
  const double thickness = scene.slice_thickness();
  bodies_.resize(state_.size(), nullptr);
  double largest_r = 0.0;
  for (std::size_t i = 0; i < state_.size(); ++i) {
    const SpeciesDef& sp = scene.charge.species[state_.species[i]];
    b2BodyDef def;
    def.type = b2_dynamicBody;
    def.position.Set(static_cast<float>(state_.position_m[i].x * units_per_m_),
                     static_cast<float>(state_.position_m[i].y * units_per_m_));
    def.linearVelocity.Set(static_cast<float>(state_.velocity_m_s[i].x * units_per_m_),
                           static_cast<float>(state_.velocity_m_s[i].y * units_per_m_));
    def.angle = static_cast<float>(state_.angle_rad[i]);
    def.angularVelocity = static_cast<float>(state_.spin_rad_s[i]);
    def.userData.pointer = i + 1;
    def.allowSleep = false;
    b2Body* body = world_->CreateBody(&def);
    b2CircleShape circle;
    circle.m_radius = static_cast<float>(state_.radius_m[i] * units_per_m_);
    b2FixtureDef fd;
    fd.shape = &circle;
    // Mass per scaled area so that the disk's mass is rho * pi r^2 * thickness in kg.
    fd.density = static_cast<float>(sp.density_kg_m3 * thickness / (units_per_m_ * units_per_m_));
    fd.friction = static_cast<float>(sp.friction);
    fd.restitution = static_cast<float>(sp.restitution);
    body->CreateFixture(&fd);
    bodies_[i] = body;
    largest_r = std::max(largest_r, state_.radius_m[i]);
  }
  velocity_before_.assign(state_.size(), Vec2{});
  spin_before_.assign(state_.size(), 0.0);
  position_before_ = state_.position_m;
  shape_band_m_ = 2.0 * largest_r;
  double smallest_r = largest_r;
  for (double r : state_.radius_m) smallest_r = std::min(smallest_r, r);
  // 2% of the smallest radius: far below anything a disk can feel, far above round-off.
  liner_tolerance_m_ = 0.02 * (smallest_r > 0.0 ? smallest_r : 0.001 * mill.radius_m);
  set_liner(mill);
  // Read Box2D's masses back (float rounding) so energies use what the solver uses.
  for (std::size_t i = 0; i < state_.size(); ++i) state_.mass_kg[i] = bodies_[i]->GetMass();
  reset_window();
}

void Box2DEngine::set_liner(const MillGeometry& mill) {
  mill_ = mill;
  if (liner_) {
    mill_body_->DestroyFixture(liner_);
    liner_ = nullptr;
  }
  const std::size_t n = mill.boundary.size();
  const std::vector<int> kept = simplify_ring(mill.boundary, liner_tolerance_m_);
  const std::size_t m = kept.size();
  coarse_start_.assign(m, 0);
  coarse_count_.assign(m, 0);
  fine_t_offset_.assign(m + 1, 0);
  fine_t_.clear();
  for (std::size_t k = 0; k < m; ++k) {
    const int i0 = kept[k];
    const int i1 = k + 1 < m ? kept[k + 1] : kept[0] + static_cast<int>(n);
    coarse_start_[k] = i0;
    coarse_count_[k] = i1 - i0;
    const Vec2 a = mill.boundary[static_cast<std::size_t>(i0)];
    const Vec2 ab = mill.boundary[static_cast<std::size_t>(i1) % n] - a;
    fine_t_offset_[k] = static_cast<int>(fine_t_.size());
    for (int j = i0 + 1; j < i1; ++j)
      fine_t_.push_back(dot(mill.boundary[static_cast<std::size_t>(j) % n] - a, ab) / length_sq(ab));
  }
  fine_t_offset_[m] = static_cast<int>(fine_t_.size());
  // One-sided chain: Box2D collides on the right of each edge, so the inner boundary runs
  // clockwise. Each vertex moves out (into the metal) by the chain's skin so the contact
  // surface sits on the drawn geometry.
  const double skin_m = b2_polygonRadius / units_per_m_;
  std::vector<b2Vec2> chain(m);
  double max_r = 0.0, min_r = 1e300;
  for (const Vec2& p : mill.boundary) {
    max_r = std::max(max_r, length(p));
    min_r = std::min(min_r, length(p));
  }
  for (std::size_t j = 0; j < m; ++j) {
    const std::size_t k = m - 1 - j;  // coarse vertex k = fine vertex kept[k]
    const std::size_t cur = k, prev = (k + m - 1) % m, next = (k + 1) % m;
    const Vec2 pc = mill.boundary[static_cast<std::size_t>(kept[cur])];
    const Vec2 e_in = pc - mill.boundary[static_cast<std::size_t>(kept[prev])];
    const Vec2 e_out = mill.boundary[static_cast<std::size_t>(kept[next])] - pc;
    const Vec2 nrm = normalized(right_perp(normalized(e_in)) + right_perp(normalized(e_out)));
    const Vec2 p = pc + skin_m * nrm;
    chain[j].Set(static_cast<float>(p.x * units_per_m_), static_cast<float>(p.y * units_per_m_));
  }
  b2ChainShape shape;
  shape.CreateLoop(chain.data(), static_cast<int32>(m));
  b2FixtureDef fd;
  fd.shape = &shape;
  fd.friction = 0.5f;     // replaced per contact in on_begin by the species' liner values
  fd.restitution = 0.3f;
  liner_ = mill_body_->CreateFixture(&fd);
  chain_count_ = static_cast<int>(m);
  edge_is_shell_.resize(n);
  for (std::size_t e = 0; e < n; ++e)
    edge_is_shell_[e] = mill.edges[e].owner == EdgeOwner::Shell ? 1 : 0;
  escape_radius_m_ = max_r + skin_m;
  band_m_ = max_r - min_r;
  edge_count_ = n;
  reset_accounting(accounting_, n);
  event_energy_J_.clear();
}

void Box2DEngine::set_mill_speed(double omega_rad_s) {
  state_.mill_speed_rad_s = omega_rad_s;
  mill_body_->SetAngularVelocity(static_cast<float>(omega_rad_s));
}

void Box2DEngine::on_begin(b2Contact* c) {
  b2Body* a = c->GetFixtureA()->GetBody();
  b2Body* b = c->GetFixtureB()->GetBody();
  if (a == mill_body_ || b == mill_body_) {
    const int disk = disk_of(a == mill_body_ ? b : a);
    const std::uint8_t sp = state_.species[static_cast<std::size_t>(disk)];
    c->SetFriction(friction_liner_[sp]);
    c->SetRestitution(restitution_liner_[sp]);
  }
}

void Box2DEngine::on_end(b2Contact* c) {
  if (!accounting_.options.collision_spectrum) return;
  double energy_J = 0.0;
  if (event_energy_J_.take(c, energy_J)) account_collision_event(accounting_, energy_J);
}

void Box2DEngine::step(int n) {
  for (int k = 0; k < n; ++k) step_once();
}

void Box2DEngine::step_once() {
  const std::size_t n = state_.size();
  for (std::size_t i = 0; i < n; ++i) {
    velocity_before_[i] = state_.velocity_m_s[i];
    spin_before_[i] = state_.spin_rad_s[i];
    position_before_[i] = state_.position_m[i];
  }
  world_->Step(static_cast<float>(dt_), velocity_iterations_, position_iterations_);
  const b2Profile& prof = world_->GetProfile();
  timing_.collide_s += 1e-3 * prof.collide;  // narrow phase; the broad phase is inside solve
  timing_.solve_s += 1e-3 * prof.solve;
  timing_.disk_steps += static_cast<std::int64_t>(n);

  const auto t0 = Clock::now();
  state_.time_s += dt_;
  state_.mill_angle_rad += state_.mill_speed_rad_s * dt_;
  // Keep the body's float angle small; the double angle above is the true one.
  const float body_angle = mill_body_->GetAngle();
  if (std::fabs(body_angle) > static_cast<float>(kPi)) {
    const double wrapped = std::remainder(state_.mill_angle_rad, 2.0 * kPi);
    mill_body_->SetTransform(b2Vec2(0.0f, 0.0f), static_cast<float>(wrapped));
  }
  read_back();
  account_contacts();
  if (accounting_.steps % kInsideLinerCheckInterval == 0) check_inside_liner();
  account_step(accounting_, state_, dt_, radius_m_, shape_band_m_ + band_m_);
  accounting_.kinetic_J_end = charge_kinetic_J(state_);
  accounting_.potential_J_end = charge_potential_J(state_, kGravity);
  timing_.account_s += seconds_since(t0);
}

void Box2DEngine::remove_disk(std::size_t i, const std::string& why) {
  state_.active[i] = 0;
  bodies_[i]->SetEnabled(false);
  events_.push_back({state_.time_s, "disk " + std::to_string(i) + " " + why});
}

void Box2DEngine::read_back() {
  const double inv = 1.0 / units_per_m_;
  const double escape_sq = escape_radius_m_ * escape_radius_m_;
  for (std::size_t i = 0; i < state_.size(); ++i) {
    if (!state_.active[i]) continue;
    const b2Body* b = bodies_[i];
    const b2Vec2 p = b->GetPosition();
    const b2Vec2 v = b->GetLinearVelocity();
    const Vec2 pos{p.x * inv, p.y * inv};
    const Vec2 vel{v.x * inv, v.y * inv};
    const double spin = b->GetAngularVelocity();
    if (!finite(pos) || !finite(vel) || !std::isfinite(spin)) {
      accounting_.non_finite += 1;
      remove_disk(i, "went non-finite");
      continue;
    }
    // What the position correction moved, beyond x + h v: its potential-energy change is
    // the solver's share of the energy balance.
    const Vec2 correction = pos - (position_before_[i] + dt_ * vel);
    accounting_.solver_position_J -= state_.mass_kg[i] * kGravity * correction.y;
    state_.position_m[i] = pos;
    state_.velocity_m_s[i] = vel;
    state_.angle_rad[i] = b->GetAngle();
    state_.spin_rad_s[i] = spin;
    if (length_sq(pos) > escape_sq) {
      accounting_.escaped += 1;
      remove_disk(i, "escaped through the shell");
    }
  }
}

void Box2DEngine::check_inside_liner() {
  // A disk whose centre got into the liner metal has leaked through a one-sided edge.
  const double inner_sq = (radius_m_ - band_m_) * (radius_m_ - band_m_);
  for (std::size_t i = 0; i < state_.size(); ++i) {
    if (!state_.active[i]) continue;
    const Vec2 p = state_.position_m[i];
    if (length_sq(p) < inner_sq) continue;
    const Vec2 pm = rotated(p, -state_.mill_angle_rad);
    if (deeper_than_liner_surface(mill_, pm, kLostDepthRadii * state_.radius_m[i])) {
      accounting_.escaped += 1;
      remove_disk(i, "leaked into the liner");
    }
  }
}

int Box2DEngine::fine_edge_of(int chain_child, Vec2 point_world) const {
  // Chain child c runs clockwise; it is coarse counter-clockwise edge K-2-c (mod K).
  const int m = chain_count_;
  const int k = ((m - 2 - chain_child) % m + m) % m;
  const int n = static_cast<int>(mill_.boundary.size());
  const int i0 = coarse_start_[static_cast<std::size_t>(k)];
  const int count = coarse_count_[static_cast<std::size_t>(k)];
  if (count <= 1) return i0;
  const Vec2 p = rotated(point_world, -state_.mill_angle_rad);
  const Vec2 a = mill_.boundary[static_cast<std::size_t>(i0)];
  const Vec2 ab = mill_.boundary[static_cast<std::size_t>((i0 + count) % n)] - a;
  const double t = dot(p - a, ab) / length_sq(ab);
  const auto first = fine_t_.begin() + fine_t_offset_[static_cast<std::size_t>(k)];
  const auto last = fine_t_.begin() + fine_t_offset_[static_cast<std::size_t>(k) + 1];
  const int j = static_cast<int>(std::upper_bound(first, last, t) - first);
  return (i0 + j) % n;
}

void Box2DEngine::account_contacts() {
  const double inv = 1.0 / units_per_m_;
  const double omega = state_.mill_speed_rad_s;
  const bool spectrum = accounting_.options.collision_spectrum;
  for (b2Contact* c = world_->GetContactList(); c; c = c->GetNext()) {
    if (!c->IsTouching() || !c->IsEnabled()) continue;
    const b2Manifold* man = c->GetManifold();
    if (man->pointCount == 0) continue;
    b2WorldManifold wm;
    c->GetWorldManifold(&wm);
    const b2Body* body_a = c->GetFixtureA()->GetBody();
    const b2Body* body_b = c->GetFixtureB()->GetBody();
    // Box2D's normal points from A to B; ours from b (or the liner) toward a.
    const b2Body* first = body_b;
    const b2Body* second = body_a;
    float sign = 1.0f;
    int child = c->GetChildIndexA();
    if (body_b == mill_body_) {
      first = body_a;
      second = body_b;
      sign = -1.0f;
      child = c->GetChildIndexB();
    }
    const bool liner = second == mill_body_;
    const int a = disk_of(first);
    const int b = liner ? -1 : disk_of(second);
    if (a < 0 || !state_.active[static_cast<std::size_t>(a)]) continue;
    if (b >= 0 && !state_.active[static_cast<std::size_t>(b)]) continue;
    const Vec2 nrm{sign * wm.normal.x, sign * wm.normal.y};
    const Vec2 tan = left_perp(nrm);
    ContactRecord rec;
    rec.a = a;
    rec.b = b;
    rec.normal = nrm;
    const auto ia = static_cast<std::size_t>(a);
    for (int k = 0; k < man->pointCount; ++k) {
      const b2ManifoldPoint& mp = man->points[k];
      const Vec2 point{wm.points[k].x * inv, wm.points[k].y * inv};
      if (liner) rec.edge = fine_edge_of(child, point);
      rec.point_m = point;
      rec.normal_impulse = mp.normalImpulse * inv;
      // Box2D's tangent is right_perp(A->B normal); ours is left_perp(our normal).
      rec.tangent_impulse = -mp.tangentImpulse * inv;
      const Vec2 ra = point - state_.position_m[ia];
      auto point_velocity = [](Vec2 v, double w, Vec2 r) { return v + w * left_perp(r); };
      Vec2 va0 = point_velocity(velocity_before_[ia], spin_before_[ia], ra);
      Vec2 va1 = point_velocity(state_.velocity_m_s[ia], state_.spin_rad_s[ia], ra);
      Vec2 vb0, vb1;
      if (liner) {
        vb0 = vb1 = omega * left_perp(point);
      } else {
        const auto ib = static_cast<std::size_t>(b);
        const Vec2 rb = point - state_.position_m[ib];
        vb0 = point_velocity(velocity_before_[ib], spin_before_[ib], rb);
        vb1 = point_velocity(state_.velocity_m_s[ib], state_.spin_rad_s[ib], rb);
      }
      const Vec2 d0 = va0 - vb0, d1 = va1 - vb1;
      rec.vn_before = dot(d0, nrm);
      rec.vn_after = dot(d1, nrm);
      rec.vt_before = dot(d0, tan);
      rec.vt_after = dot(d1, tan);
      const bool shell = liner && edge_is_shell_[static_cast<std::size_t>(rec.edge)];
      account_contact(accounting_, rec, omega, shell);
      if (spectrum && !liner) {
        const double loss = -rec.normal_impulse * 0.5 * (rec.vn_before + rec.vn_after) -
                            rec.tangent_impulse * 0.5 * (rec.vt_before + rec.vt_after);
        event_energy_J_.add(c, loss);
      }
    }
  }
}

}  // namespace

std::unique_ptr<Engine> make_box2d_engine(const Scene& scene, const MillGeometry& mill,
                                          const ChargeState& initial,
                                          const AccountingOptions& opts) {
  return std::make_unique<Box2DEngine>(scene, mill, initial, opts);
}

}  // namespace millwear
