// The probe mill of bench/probe_scene.hpp on Box2D v3, one thread: the reference the soft
// backend's speed is compared against (docs/benchmarks.md, "Against Box2D v3"). Box2D v3 is
// not a Debian package, so this program is built on its own against a Box2D v3 source tree
// (CMakeLists.txt here), never by the project's build.
//
// Scene: a 5.0 m mill, 24 trapezoid lifters (0.15 m high, 0.10 m top, faces 30 deg to the
// radial line), 8 shell segments per gap, the whole inner boundary one closed loop chain
// (clockwise: normals inward) on one kinematic body at 75% of critical speed. Disks fill
// 0.8 x 30% of the mill area, radii uniform in [r, 1.67 r], density 2700 kg/m^3, friction
// 0.5, restitution 0.4, rolling resistance 0.05. Box2D's tolerances are in length units, so
// the model is scaled to make the mean disk 0.75 units across (lengths, gravity and speeds
// times S; time is not scaled). dt 1/600 s, 4 substeps, contact stiffness 300 Hz, push-out
// 1 m/s: softer contacts at Box2D's defaults let the bed sink through the shell.
// Settle 2 s with the mill at rest, turn one revolution at full speed, then time one more.
//
// usage: box2d_v3_probe r_min_m [substeps hertz pushout_m_s settle_s spinup_rev timed_rev]
//   r_min_m 0.0287 / 0.0166 / 0.0091: about 1,000 / 3,000 / 10,000 disks.
// Prints disk-steps per CPU second and per wall second, and the disks outside the mill.
#include <box2d/box2d.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <utility>
#include <vector>

static double now(clockid_t c) {
  timespec ts{};
  clock_gettime(c, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s r_min_m [substeps hertz pushout_m_s settle_s spinup_rev timed_rev]\n", argv[0]);
    return 2;
  }
  const double r_min = std::atof(argv[1]);
  const int substeps = argc > 2 ? std::atoi(argv[2]) : 4;
  const double hertz = argc > 3 ? std::atof(argv[3]) : 300.0;
  const double pushout = argc > 4 ? std::atof(argv[4]) : 1.0;  // m/s, physical
  const double settle_s = argc > 5 ? std::atof(argv[5]) : 2.0;
  const double spinup_rev = argc > 6 ? std::atof(argv[6]) : 1.0;
  const double timed_rev = argc > 7 ? std::atof(argv[7]) : 1.0;

  const double PI = 3.14159265358979323846;
  const double g = 9.81;
  const double D = 5.0, R = D / 2;
  const double omega_c = std::sqrt(g / R);
  const double omega = 0.75 * omega_c;  // 1.486 rad/s
  const double dt = 1.0 / 600.0;
  const int rows = 24;
  const double lh = 0.15, ltop = 0.10, face = 30.0 * PI / 180.0;
  const int shell_segs = 8;
  const double r_max = 1.67 * r_min;
  const double mean_d = r_min + r_max;  // mean diameter = 2 * (r_min + r_max) / 2
  const double S = 0.75 / mean_d;       // model units per metre

  // Disk count: 0.8 x 30% of pi R^2 over the mean disk area pi E[r^2].
  const double Er2 = (r_min * r_min + r_min * r_max + r_max * r_max) / 3.0;
  const int N = static_cast<int>(std::lround(0.8 * 0.30 * R * R / Er2));

  // World.
  b2WorldDef wd = b2DefaultWorldDef();
  wd.gravity = {0.0f, static_cast<float>(-g * S)};
  wd.contactHertz = static_cast<float>(hertz);
  wd.contactSpeed = static_cast<float>(pushout * S);
  wd.restitutionThreshold = static_cast<float>(1.0 * S);   // default 1 m/s, scaled
  wd.maximumLinearSpeed = static_cast<float>(400.0 * S);   // default 400 m/s, scaled
  wd.workerCount = 1;
  b2WorldId world = b2CreateWorld(&wd);

  // Liner: CCW points, then reversed to clockwise (normals point into the mill).
  std::vector<b2Vec2> ccw;
  for (int k = 0; k < rows; ++k) {
    const double th = 2 * PI * k / rows;
    const double ux = std::cos(th), uy = std::sin(th), tx = -std::sin(th), ty = std::cos(th);
    // side -1: the clockwise side of the lifter, +1: the counter-clockwise side.
    // A corner of the lifter's top: the face starts there.
    auto top_corner = [&](double side) {
      return std::pair<double, double>{(R - lh) * ux + side * 0.5 * ltop * tx, (R - lh) * uy + side * 0.5 * ltop * ty};
    };
    // Where the face from that corner meets the shell: |p + s d| = R, d a unit vector.
    auto base_point = [&](double side) {
      const auto [px, py] = top_corner(side);
      const double dx = std::cos(face) * ux + side * std::sin(face) * tx;
      const double dy = std::cos(face) * uy + side * std::sin(face) * ty;
      const double b = px * dx + py * dy, c = px * px + py * py - R * R;
      const double s = -b + std::sqrt(b * b - c);
      return b2Vec2{static_cast<float>(px + s * dx), static_cast<float>(py + s * dy)};
    };
    auto point = [](std::pair<double, double> p) {
      return b2Vec2{static_cast<float>(p.first), static_cast<float>(p.second)};
    };
    const b2Vec2 b0 = base_point(-1), b1 = base_point(+1);
    ccw.push_back(b0);
    ccw.push_back(point(top_corner(-1)));
    ccw.push_back(point(top_corner(+1)));
    ccw.push_back(b1);
    // shell arc from b1 to the next lifter's b0, 8 segments (7 interior points)
    // angular half-width of the lifter base, measured in the lifter's own frame (no wrap-around)
    const double half = std::atan2(b1.x * tx + b1.y * ty, b1.x * ux + b1.y * uy);
    const double a0 = th + half;
    const double a1 = th + 2 * PI / rows - half;
    for (int j = 1; j < shell_segs; ++j) {
      const double a = a0 + (a1 - a0) * j / shell_segs;
      ccw.push_back({static_cast<float>(R * std::cos(a)), static_cast<float>(R * std::sin(a))});
    }
  }
  std::vector<b2Vec2> pts(ccw.rbegin(), ccw.rend());
  for (auto& p : pts) p = {static_cast<float>(p.x * S), static_cast<float>(p.y * S)};

  b2BodyDef mbd = b2DefaultBodyDef();
  mbd.type = b2_kinematicBody;
  b2BodyId mill = b2CreateBody(world, &mbd);
  b2SurfaceMaterial mat = b2DefaultSurfaceMaterial();
  mat.friction = 0.5f;
  mat.restitution = 0.4f;
  mat.rollingResistance = 0.05f;
  b2ChainDef cd = b2DefaultChainDef();
  cd.points = pts.data();
  cd.count = static_cast<int>(pts.size());
  cd.materials = &mat;
  cd.materialCount = 1;
  cd.isLoop = true;
  b2CreateChain(mill, &cd);

  // Disks on a jittered square grid in the lower part of the mill, inside the lifter tips.
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double cell = 2 * r_max * 1.05;
  const double rin = R - lh - 0.05;
  std::vector<b2BodyId> disks;
  disks.reserve(N);
  b2ShapeDef sd = b2DefaultShapeDef();
  sd.density = 2700.0f;
  sd.material = mat;
  for (double y = -rin + cell / 2; y < rin && static_cast<int>(disks.size()) < N; y += cell) {
    for (double x = -rin + cell / 2; x < rin && static_cast<int>(disks.size()) < N; x += cell) {
      if (std::hypot(x, y) + cell / 2 > rin) continue;
      const double r = r_min + (r_max - r_min) * U(rng);
      const double jx = (U(rng) - 0.5) * (cell - 2 * r), jy = (U(rng) - 0.5) * (cell - 2 * r);
      b2BodyDef bd = b2DefaultBodyDef();
      bd.type = b2_dynamicBody;
      bd.position = {static_cast<float>((x + jx) * S), static_cast<float>((y + jy) * S)};
      b2BodyId b = b2CreateBody(world, &bd);
      b2Circle c{{0.0f, 0.0f}, static_cast<float>(r * S)};
      b2CreateCircleShape(b, &sd, &c);
      disks.push_back(b);
    }
  }
  if (static_cast<int>(disks.size()) < N) {
    std::fprintf(stderr, "only placed %zu of %d disks\n", disks.size(), N);
    return 1;
  }

  auto escaped = [&]() {
    int n = 0;
    const double lim = R * S;
    for (auto b : disks) {
      const b2Vec2 p = b2ToVec2(b2Body_GetPosition(b));
      if (std::hypot(p.x, p.y) > lim) ++n;
    }
    return n;
  };

  const float fdt = static_cast<float>(dt);
  const int settle_steps = static_cast<int>(std::lround(settle_s / dt));
  const double rev_s = 2 * PI / omega;
  const int spin_steps = static_cast<int>(std::lround(spinup_rev * rev_s / dt));
  const int timed_steps = static_cast<int>(std::lround(timed_rev * rev_s / dt));

  std::printf("Box2D v3 probe: r_min %.4f m, %d disks, %zu chain points, S %.3f units/m, omega %.4f rad/s,\n"
              "  dt 1/%.0f s, %d substeps, %.0f Hz, push-out %.3g m/s (%.3g units/s), settle %.2f s (%d steps), "
              "spin-up %.2f rev (%d steps), timed %.2f rev (%d steps)\n",
              r_min, N, pts.size(), S, omega, 1 / dt, substeps, hertz, pushout, pushout * S, settle_s, settle_steps,
              spinup_rev, spin_steps, timed_rev, timed_steps);
  std::fflush(stdout);

  for (int i = 0; i < settle_steps; ++i) b2World_Step(world, fdt, substeps);
  const int esc_settle = escaped();
  b2Body_SetAngularVelocity(mill, static_cast<float>(omega));
  for (int i = 0; i < spin_steps; ++i) b2World_Step(world, fdt, substeps);
  const int esc_spin = escaped();

  // Timed revolution; the charge centre of mass is sampled every 60 steps (not timed).
  double cpu = 0, wall = 0, xcm_sum = 0, ycm_sum = 0;
  int samples = 0;
  for (int done = 0; done < timed_steps;) {
    const int chunk = std::min(60, timed_steps - done);
    const double c0 = now(CLOCK_THREAD_CPUTIME_ID), w0 = now(CLOCK_MONOTONIC);
    for (int i = 0; i < chunk; ++i) b2World_Step(world, fdt, substeps);
    cpu += now(CLOCK_THREAD_CPUTIME_ID) - c0;
    wall += now(CLOCK_MONOTONIC) - w0;
    done += chunk;
    double sx = 0, sy = 0, sm = 0;
    for (auto b : disks) {
      const b2Vec2 p = b2ToVec2(b2Body_GetPosition(b));
      if (std::hypot(p.x, p.y) > R * S) continue;
      const double m = b2Body_GetMass(b);
      sx += m * p.x;
      sy += m * p.y;
      sm += m;
    }
    xcm_sum += sx / sm / S;
    ycm_sum += sy / sm / S;
    ++samples;
  }
  const int esc_end = escaped();
  const double disk_steps = static_cast<double>(N) * timed_steps;
  // Torque-arm power omega M g |x_cm| per metre of mill (physical units).
  const double mass_per_m = 2700.0 * PI * Er2 * (N - esc_end);
  const double xcm = xcm_sum / samples, ycm = ycm_sum / samples;
  b2Counters ctr = b2World_GetCounters(world);
  std::printf("RESULT disks %d steps %d cpu_s %.3f wall_s %.3f disk_steps_per_cpu_s %.4g disk_steps_per_wall_s %.4g "
              "sim_s_per_cpu_s %.4g escaped_settle %d escaped_spinup %d escaped_end %d\n",
              N, timed_steps, cpu, wall, disk_steps / cpu, disk_steps / wall, timed_steps * dt / cpu, esc_settle,
              esc_spin, esc_end);
  std::printf("  charge x_cm %.3f m y_cm %.3f m, torque-arm power omega M g |x_cm| %.1f kW/m; contacts %d\n", xcm, ycm,
              omega * mass_per_m * g * std::fabs(xcm) / 1000.0, ctr.contactCount);
  b2DestroyWorld(world);
  return 0;
}
