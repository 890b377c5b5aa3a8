// The window of `millwear view`: GLFW + OpenGL 3 + Dear ImGui. The mill is drawn with ImGui's
// background draw list (disks, liner, lifters, trails, markers) on the left square; the panel
// of controls and readouts fills the right. Frames advance the mill by 1/60 s of
// simulated time each when run without a person (--frames, --script), by the wall time
// between frames otherwise.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "scene/limits.hpp"
#include "study/charge_run.hpp"
#include "view/live_mill.hpp"
#include "view/png.hpp"
#include "view/script.hpp"
#include "view/view.hpp"

namespace millwear::view {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kFrameSimS = 1.0 / 60.0;  // simulated time per frame without a person
// The most simulated time one frame advances with a person watching: below 4 frames a second
// the mill slows rather than jumps.
constexpr double kSlowestFrameS = 0.25;

// Colours (RGB). The species colours appear nowhere else in the window, so a screenshot
// shows where the disks are by colour alone.
constexpr ImU32 rgb(int r, int g, int b) { return IM_COL32(r, g, b, 255); }
const ImU32 kBackground = rgb(22, 22, 26);
const ImU32 kInterior = rgb(44, 44, 52);
const ImU32 kMetal = rgb(118, 118, 128);
const ImU32 kSpecies[] = {rgb(66, 135, 245), rgb(214, 160, 90), rgb(120, 200, 120), rgb(220, 90, 200)};
const ImU32 kArrow = rgb(235, 235, 235);
const ImU32 kToe = rgb(255, 140, 0), kShoulder = rgb(255, 60, 60), kCentre = rgb(250, 250, 250);
const ImU32 kTrail = rgb(250, 230, 80);
const ImU32 kGhost = IM_COL32(255, 255, 255, 140);

// Blue -> green -> yellow -> red over [0, 1].
ImU32 ramp(double v) {
  v = std::clamp(v, 0.0, 1.0);
  const double r = std::clamp(2.0 * v - 0.5, 0.0, 1.0), g = v < 0.75 ? std::min(1.0, 2.0 * v) : 4.0 * (1.0 - v);
  const double b = std::clamp(1.0 - 2.0 * v, 0.0, 1.0);
  return IM_COL32(static_cast<int>(40 + 215 * r), static_cast<int>(40 + 200 * g), static_cast<int>(60 + 180 * b), 255);
}

struct Pane {
  float cx, cy, scale;  // pixels per metre
  ImVec2 at(Vec2 p) const { return ImVec2(cx + static_cast<float>(p.x) * scale, cy - static_cast<float>(p.y) * scale); }
};

struct UiState {
  float speed = 0.75f, filling = 0.3f, ball_filling = 0.3f, time_scale = 1.0f;
  float height_mm = 0, lead_deg = 0, trail_deg = 0;
  float wear_hours = 200.0f;
  int reverse = 0, trails = 4;
  bool colour_by_speed = false;
  char profile_path[512] = "";
  char save_path[512] = "view-scene.toml";
  char shot_path[512] = "view.png";
  char record_dir[512] = "view-frames";
  std::string message;     // the last refusal (or file written)
  std::string shot_pending;  // a screenshot asked for in the panel, taken at the next frame
  bool recording = false;
  int record_index = 0;
  std::string record_to;
  std::vector<std::string> shipped_profiles;
  std::vector<RunInput> inputs;  // the scene on screen and the script: never written over
};

void sync_ui(UiState& ui, const LiveMill& s) {
  const Scene& sc = s.scene();
  ui.speed = static_cast<float>(sc.mill.speed_fraction_critical);
  ui.filling = static_cast<float>(sc.charge.filling);
  ui.ball_filling = static_cast<float>(sc.charge.ball_filling);
  ui.reverse = sc.mill.direction == Direction::Reverse ? 1 : 0;
  ui.height_mm = static_cast<float>(s.lifter_height_mm());
  ui.lead_deg = static_cast<float>(s.leading_face_deg());
  ui.trail_deg = static_cast<float>(s.trailing_face_deg());
  ui.time_scale = static_cast<float>(s.time_scale());
}

std::vector<std::string> profiles_beside(const std::string& profile_file) {
  std::set<std::string> files;
  std::error_code ec;
  const fs::path dir = fs::path(profile_file).parent_path();
  for (const auto& e : fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec))
    if (e.path().extension() == ".toml") files.insert(e.path().string());
  return {files.begin(), files.end()};
}

// The liner of `mill` at mill angle `angle`: lifters filled, the surface as a path whose
// edges take `edge_colour`.
void draw_liner(ImDrawList* dl, const Pane& pane, const MillGeometry& mill, double angle,
                const std::vector<double>& edge_value, double value_max) {
  const int rows = mill.rows;
  for (int row = 0; row < rows; ++row) {
    const LinerUnit& u = mill.units[mill.unit_of_row(row)];  // a pattern: one unit per kind
    std::vector<ImVec2> poly;
    for (const Vec2& p : u.surface)
      if (std::fabs(p.x) <= 1.05 * u.lifter_half_base_m) poly.push_back(pane.at(rotated(local_to_mill(p, row, rows, mill.radius_m), angle)));
    if (poly.size() >= 3) dl->AddConvexPolyFilled(poly.data(), static_cast<int>(poly.size()), kMetal);
  }
  const std::size_t n = mill.boundary.size();
  for (std::size_t e = 0; e < n; ++e) {
    const ImVec2 a = pane.at(rotated(mill.boundary[e], angle)), b = pane.at(rotated(mill.boundary[(e + 1) % n], angle));
    const double v = e < edge_value.size() && value_max > 0 ? edge_value[e] / value_max : 0.0;
    dl->AddLine(a, b, ramp(v), 3.0f);
  }
}

void draw_ghost(ImDrawList* dl, const Pane& pane, const MillGeometry& mill, double angle) {
  const std::size_t n = mill.boundary.size();
  for (std::size_t e = 0; e < n; ++e)
    dl->AddLine(pane.at(rotated(mill.boundary[e], angle)), pane.at(rotated(mill.boundary[(e + 1) % n], angle)), kGhost, 1.0f);
}

double percentile98(const std::vector<double>& v) {
  std::vector<double> all;
  for (double x : v)
    if (std::isfinite(x) && x > 0) all.push_back(x);
  if (all.empty()) return 0.0;
  const std::size_t k = std::min(all.size() - 1, static_cast<std::size_t>(0.98 * all.size()));
  std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(k), all.end());
  return all[k];
}

// Where on the shell an angle from 6 o'clock (+ on the rising side) is.
Vec2 shell_point(double deg, double dir, double r) {
  const double a = rad_from_deg(deg);
  return Vec2{dir * r * std::sin(a), -r * std::cos(a)};
}

void draw_mill(const LiveMill& s, const WearView& wear, bool show_wear, const Pane& pane, bool by_speed) {
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const Scene& sc = s.scene();
  const double R = sc.radius_m();
  const ChargeState& c = show_wear ? wear.charge : s.charge();
  const MillGeometry& mill = show_wear ? wear.mill : s.mill();
  const double angle = c.mill_angle_rad;
  dl->AddCircleFilled(pane.at({0, 0}), static_cast<float>(R * pane.scale), kInterior, 128);
  static const std::vector<double> none;
  const std::vector<double>& ev = show_wear ? none : s.edge_shear_W_m2();
  draw_liner(dl, pane, mill, angle, ev, percentile98(ev));
  if (show_wear || s.mill().boundary.size() != s.new_mill().boundary.size() ||
      s.mill().boundary != s.new_mill().boundary)
    draw_ghost(dl, pane, s.new_mill(), angle);
  // Disks.
  const double v_ref = sc.critical_speed_rad_s() * R;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c.active[i]) continue;
    ImU32 col = kSpecies[c.species[i] % 4];
    if (by_speed) col = ramp(length(c.velocity_m_s[i]) / v_ref);
    dl->AddCircleFilled(pane.at(c.position_m[i]), std::max(1.0f, static_cast<float>(c.radius_m[i] * pane.scale)), col, 16);
  }
  if (!show_wear) {
    for (const auto& t : s.trails()) {
      std::vector<ImVec2> pts;
      for (const Vec2& p : t) pts.push_back(pane.at(p));
      if (pts.size() >= 2) dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), kTrail, 0, 1.5f);
    }
  }
  // Direction of rotation: an arc outside the shell, top right, with its head.
  const double dir = c.mill_speed_rad_s < 0 ? -1.0 : 1.0;
  const float rr = static_cast<float>(1.04 * R * pane.scale);
  const ImVec2 o = pane.at({0, 0});
  const float a0 = -1.2f, a1 = -0.4f;  // screen angles (y down)
  dl->PathArcTo(o, rr, a0, a1, 24);
  dl->PathStroke(kArrow, 0, 3.0f);
  const float tip = dir > 0 ? a0 : a1;  // counter-clockwise on screen: toward smaller angle
  const float back = tip + (dir > 0 ? 0.12f : -0.12f);
  const ImVec2 p_tip(o.x + rr * std::cos(tip), o.y + rr * std::sin(tip));
  const ImVec2 p1(o.x + (rr + 9) * std::cos(back), o.y + (rr + 9) * std::sin(back));
  const ImVec2 p2(o.x + (rr - 9) * std::cos(back), o.y + (rr - 9) * std::sin(back));
  dl->AddTriangleFilled(p_tip, p1, p2, kArrow);
  // Toe, shoulder (outside the shell) and the centre of mass, from the last batch.
  if (!show_wear && !s.readouts().empty()) {
    const Readout& r = s.readouts().back();
    if (!r.centrifuged && std::isfinite(r.toe_deg) && std::isfinite(r.shoulder_deg)) {
      dl->AddCircleFilled(pane.at(shell_point(r.toe_deg, dir, 1.06 * R)), 6.0f, kToe);
      dl->AddCircleFilled(pane.at(shell_point(r.shoulder_deg, dir, 1.06 * R)), 6.0f, kShoulder);
    }
    const ImVec2 m = pane.at(r.centre_of_mass_m);
    dl->AddLine(ImVec2(m.x - 7, m.y), ImVec2(m.x + 7, m.y), kCentre, 2.0f);
    dl->AddLine(ImVec2(m.x, m.y - 7), ImVec2(m.x, m.y + 7), kCentre, 2.0f);
  }
}

// Why a recording may not start in `dir` ("" if it may): it is a file, or holds frame_NNNNN.png
// already (an earlier recording's, or a user's). Their numbers would be written over, and a
// shorter recording would leave the rest of them behind its own, in the film made of the folder.
std::string recording_refusal(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return "";
  if (!fs::is_directory(dir, ec)) return "a folder for the recording's frames, but it is a file";
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string n = e.path().filename().string();
    if (n.rfind("frame_", 0) == 0 && e.path().extension() == ".png")
      return "a folder without frames for the recording (frame_NNNNN.png), but it holds " + n +
             ", of an earlier recording or not: record into another folder, or move them";
  }
  return "";
}

// A screenshot goes to a free name or over a PNG the view wrote (own_files.hpp): else
// InputError naming the file (and `where`, the option).
void check_screenshot(const std::string& file, const std::vector<RunInput>& inputs, const std::string& where) {
  if (const std::string r = png_refusal(file, inputs); !r.empty())
    throw InputError(file, where, "a free name for the screenshot, or a PNG millwear view wrote there: " + r +
                                      "; write the screenshot under another name");
}

void refuse_or_clear(UiState& ui, const std::string& r, LiveMill& s) {
  ui.message = r;
  if (!r.empty()) sync_ui(ui, s);  // the panel shows the values in use again
}

void draw_panel(LiveMill& s, UiState& ui, float x0, float w, float h, double fps, double ratio,
                const WearView& wear, std::vector<std::function<void()>>& actions) {
  ImGui::SetNextWindowPos(ImVec2(x0, 0));
  ImGui::SetNextWindowSize(ImVec2(w, h));
  ImGui::Begin("millwear view", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  const Scene& sc = s.scene();
  ImGui::Text("%s   t = %.1f s   %zu disks", sc.name.c_str(), s.clock_s(), s.active_disks());
  ImGui::Text("%.0f frames/s, simulated/real %.2f", fps, ratio);
  if (s.phase() == Phase::Settling) ImGui::TextUnformatted("settling (mill at rest)");
  if (s.lost_disks() > 0) ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "%zu disks lost", s.lost_disks());
  if (!ui.message.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", ui.message.c_str()), ImGui::Separator();

  if (ImGui::CollapsingHeader("Mill", ImGuiTreeNodeFlags_DefaultOpen)) {
    // The scene checker's bounds (a script's speed is held to them too), typed values clamped.
    ImGui::SliderFloat("speed (x critical)", &ui.speed, static_cast<float>(kMinSpeedFraction),
                       static_cast<float>(kMaxSpeedFraction), "%.2f", ImGuiSliderFlags_AlwaysClamp);
    if (ImGui::IsItemDeactivatedAfterEdit()) actions.push_back([&s, &ui, v = ui.speed] { refuse_or_clear(ui, s.set_speed(v), s); });
    ImGui::SliderFloat("filling", &ui.filling, 0.0f, 0.6f, "%.3f");
    if (ImGui::IsItemDeactivatedAfterEdit())
      actions.push_back([&s, &ui, f = ui.filling, b = ui.ball_filling] { refuse_or_clear(ui, s.set_filling(f, b), s); });
    ImGui::SliderFloat("ball filling", &ui.ball_filling, 0.0f, 0.6f, "%.3f");
    if (ImGui::IsItemDeactivatedAfterEdit())
      actions.push_back([&s, &ui, f = ui.filling, b = ui.ball_filling] { refuse_or_clear(ui, s.set_filling(f, b), s); });
    if (ImGui::RadioButton("forward", ui.reverse == 0)) actions.push_back([&s, &ui] { refuse_or_clear(ui, s.set_direction(false), s); });
    ImGui::SameLine();
    if (ImGui::RadioButton("reverse", ui.reverse == 1)) actions.push_back([&s, &ui] { refuse_or_clear(ui, s.set_direction(true), s); });
  }
  if (ImGui::CollapsingHeader("Lifters", ImGuiTreeNodeFlags_DefaultOpen)) {
    const std::string current = fs::path(s.profile_file()).filename().string();
    if (ImGui::BeginCombo("profile", current.c_str())) {
      for (const auto& p : ui.shipped_profiles)
        if (ImGui::Selectable(fs::path(p).filename().string().c_str(), p == s.profile_file()))
          actions.push_back([&s, &ui, p] { refuse_or_clear(ui, s.set_profile(p), s); });
      ImGui::EndCombo();
    }
    ImGui::InputText("file", ui.profile_path, sizeof ui.profile_path);
    ImGui::SameLine();
    if (ImGui::Button("load")) actions.push_back([&s, &ui, p = std::string(ui.profile_path)] { refuse_or_clear(ui, s.set_profile(p), s); });
    if (s.lifter_is_trapezoid()) {
      bool edit = false;
      ImGui::InputFloat("height mm", &ui.height_mm, 0, 0, "%.1f");
      edit |= ImGui::IsItemDeactivatedAfterEdit();
      ImGui::InputFloat("leading face deg", &ui.lead_deg, 0, 0, "%.1f");
      edit |= ImGui::IsItemDeactivatedAfterEdit();
      ImGui::InputFloat("trailing face deg", &ui.trail_deg, 0, 0, "%.1f");
      edit |= ImGui::IsItemDeactivatedAfterEdit();
      if (edit)
        actions.push_back([&s, &ui, h = ui.height_mm, a = ui.lead_deg, b = ui.trail_deg] {
          refuse_or_clear(ui, s.set_lifter_shape(h, a, b), s);
        });
    }
  }
  if (ImGui::CollapsingHeader("Run", ImGuiTreeNodeFlags_DefaultOpen)) {
    bool paused = s.paused();
    if (ImGui::Checkbox("pause", &paused)) s.set_paused(paused);
    ImGui::SameLine();
    if (ImGui::Button("step")) actions.push_back([&s] { s.step_frame(kFrameSimS); });
    ImGui::SameLine();
    if (ImGui::Button("reset")) actions.push_back([&s, &ui] { refuse_or_clear(ui, s.reset(), s); });
    if (ImGui::SliderFloat("time scale", &ui.time_scale, 0.05f, 4.0f, "%.2f")) s.set_time_scale(ui.time_scale);
    ImGui::Checkbox("colour by speed", &ui.colour_by_speed);
    if (ImGui::SliderInt("trails", &ui.trails, 0, 16)) s.set_trail_count(ui.trails);
  }
  if (ImGui::CollapsingHeader("Readouts", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (!s.readouts().empty()) {
      const Readout& r = s.readouts().back();
      ImGui::Text("power     %8.2f kW/m  %8.1f kW/mill  %6.2f kW/t", r.power_kW_per_m, r.power_kW_per_mill, r.power_kW_per_t);
      ImGui::Text("collision %8.2f kW/m  utilisation %.3f", r.collision_kW_per_m, r.utilisation);
      ImGui::Text("liner shear %6.3f kW/m", r.liner_shear_kW_per_m);
      if (r.centrifuged) ImGui::TextUnformatted("centrifuged: no toe or shoulder");
      else ImGui::Text("toe %.0f deg  shoulder %.0f deg (from 6 o'clock)", r.toe_deg, r.shoulder_deg);
      const SteadyPower p = s.steady_power();
      if (p.batches > 1) ImGui::Text("since the last change: %.2f +- %.2f kW/m (%d batches)", p.mean_kW_per_m, p.sem_kW_per_m, p.batches);
      else if (p.batches == 1) ImGui::Text("since the last change: %.2f kW/m (1 batch: no error yet)", p.mean_kW_per_m);
      std::vector<float> power;
      for (const Readout& x : s.readouts()) power.push_back(static_cast<float>(x.power_kW_per_m));
      ImGui::PlotLines("kW/m", power.data(), static_cast<int>(power.size()), 0, nullptr, FLT_MAX, FLT_MAX, ImVec2(0, 60));
    } else {
      ImGui::TextUnformatted("readouts after the first half revolution");
    }
  }
  if (ImGui::CollapsingHeader("Wear", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::InputFloat("hours", &ui.wear_hours, 0, 0, "%.0f");
    if (!wear.running) {
      if (ImGui::Button("start wear")) actions.push_back([&s, &ui, h = ui.wear_hours] { refuse_or_clear(ui, s.start_wear(h), s); });
    } else if (ImGui::Button("stop wear")) {
      actions.push_back([&s] { s.stop_wear(); });
    }
    if (wear.running || wear.finished)
      ImGui::Text("stage %d, %.0f of %.0f h, lifter area lost %.1f%%", wear.stage, wear.hours, wear.target_hours,
                  100.0 * wear.area_lost_share);
    if (!wear.message.empty()) ImGui::TextWrapped("%s", wear.message.c_str());
  }
  if (ImGui::CollapsingHeader("Keep", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::InputText("scene file", ui.save_path, sizeof ui.save_path);
    if (ImGui::Button("save scene"))
      actions.push_back([&s, &ui, f = std::string(ui.save_path)] {
        try {
          s.save_scene(f, ui.inputs);
          ui.message = "saved " + f;
        } catch (const std::exception& x) {
          ui.message = x.what();
        }
      });
    ImGui::InputText("png", ui.shot_path, sizeof ui.shot_path);
    ImGui::SameLine();
    if (ImGui::Button("screenshot")) ui.shot_pending = ui.shot_path;
    ImGui::InputText("frames folder", ui.record_dir, sizeof ui.record_dir);
    if (ImGui::Button(ui.recording ? "stop recording" : "record")) {
      const std::string refused = ui.recording ? "" : recording_refusal(ui.record_dir);
      if (refused.empty()) {
        ui.recording = !ui.recording;
        ui.record_to = ui.record_dir;
        ui.record_index = 0;
      } else {
        ui.message = std::string(ui.record_dir) + ": " + refused;
      }
    }
  }
  ImGui::End();
}

std::vector<std::uint8_t> read_window(int w, int h) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h * 3), flipped(px.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, px.data());
  const std::size_t row = static_cast<std::size_t>(w) * 3;
  for (int y = 0; y < h; ++y)
    std::copy(px.begin() + static_cast<std::ptrdiff_t>(row * (h - 1 - y)), px.begin() + static_cast<std::ptrdiff_t>(row * (h - y)),
              flipped.begin() + static_cast<std::ptrdiff_t>(row * y));
  return flipped;
}

std::string report_line(const LiveMill& s) {
  char buf[512];
  const SteadyPower p = s.steady_power();
  // What is not measured yet is nan (the power before the first batch; the steady mean and
  // its error, steady_power's), so that no one reads it as a measured zero.
  std::string shape = "no readout yet";
  double power = std::nan("");
  if (!s.readouts().empty()) {
    const Readout& r = s.readouts().back();
    power = r.power_kW_per_m;
    char b[128];
    if (r.centrifuged) std::snprintf(b, sizeof b, "centrifuged");
    else std::snprintf(b, sizeof b, "toe %.0f shoulder %.0f", r.toe_deg, r.shoulder_deg);
    shape = b;
  }
  const ChargeState& c = s.charge();
  bool finite = true;
  for (std::size_t i = 0; i < c.size(); ++i)
    if (c.active[i] && !(std::isfinite(c.position_m[i].x) && std::isfinite(c.position_m[i].y))) finite = false;
  const WearView w = s.wear_view();
  std::snprintf(buf, sizeof buf,
                "t=%.3f speed=%.4g disks=%zu lost=%zu finite=%d power_kW_per_m=%.6g steady_kW_per_m=%.6g "
                "steady_sem_kW_per_m=%.6g steady_batches=%d wear_hours=%.6g wear_area_lost=%.4f shape=%s",
                s.clock_s(), s.scene().mill.speed_fraction_critical, s.active_disks(), s.lost_disks(), finite ? 1 : 0,
                power, p.mean_kW_per_m, p.sem_kW_per_m, p.batches, w.hours, w.area_lost_share, shape.c_str());
  std::string line = buf;
  if (!w.message.empty()) line += " (wear: " + w.message + ")";
  return line;
}

// GLFW and Dear ImGui for one run: a window of the asked size with an OpenGL 3.3 context,
// all closed again when this goes.
class ViewWindow {
 public:
  ViewWindow(int width, int height, const std::string& title, bool headless) {
    if (!glfwInit()) throw RunError("cannot open a window: no display (set DISPLAY, or run under xvfb-run)");
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
    if (!window_) {
      glfwTerminate();
      throw RunError("cannot open an OpenGL 3.3 window (no display, or no OpenGL 3.3 driver)");
    }
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(headless ? 0 : 1);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // nothing written beside the working folder
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330");
  }
  ~ViewWindow() {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window_);
    glfwTerminate();
  }
  ViewWindow(const ViewWindow&) = delete;
  ViewWindow& operator=(const ViewWindow&) = delete;
  GLFWwindow* get() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

// What a script command asks of the live mill or the window; returns why the mill refused it
// ("" when it did not). A screenshot is taken with this frame (shot), a `quit` ends the run
// after it. Errors name the script's line.
std::string run_script_command(const ScriptCommand& c, LiveMill& live, UiState& ui, const ViewHooks& hooks,
                               std::string& shot, bool& quit) {
  auto num = [&c](int k) { return std::strtod(c.args[static_cast<std::size_t>(k)].c_str(), nullptr); };
  std::string refused;
  try {
    if (c.name == "speed") refused = live.set_speed(num(0));
    else if (c.name == "filling") refused = live.set_filling(num(0), c.args.size() > 1 ? num(1) : live.scene().charge.ball_filling);
    else if (c.name == "direction") refused = live.set_direction(c.args[0] == "reverse");
    else if (c.name == "profile") refused = live.set_profile(c.args[0]);
    else if (c.name == "lifter") refused = live.set_lifter_shape(num(0), num(1), num(2));
    else if (c.name == "pause") live.set_paused(true);
    else if (c.name == "resume") live.set_paused(false);
    else if (c.name == "reset") refused = live.reset();
    else if (c.name == "time_scale") live.set_time_scale(num(0));
    else if (c.name == "colour") ui.colour_by_speed = c.args[0] == "speed";
    else if (c.name == "trails") live.set_trail_count(static_cast<int>(num(0)));
    else if (c.name == "wear") refused = live.start_wear(num(0));
    else if (c.name == "wait_wear") live.wait_wear();
    else if (c.name == "save_scene") {
      for (const auto& f : live.save_scene(c.args[0], ui.inputs))
        if (hooks.notice) hooks.notice("wrote " + f);
    } else if (c.name == "save_profiles") {
      live.write_wear_profiles(c.args[0]);
      if (hooks.notice) hooks.notice("wrote the wear history's profiles into " + c.args[0]);
    } else if (c.name == "screenshot") {
      check_screenshot(c.args[0], ui.inputs, "");
      shot = c.args[0];
    }
    else if (c.name == "record") {
      if (const std::string r = recording_refusal(c.args[0]); !r.empty()) throw InputError(c.args[0], "", r);
      ui.recording = true, ui.record_to = c.args[0], ui.record_index = 0;
    }
    else if (c.name == "stop_record") ui.recording = false;
    else if (c.name == "report") { if (hooks.report) hooks.report(report_line(live)); }
    else if (c.name == "quit") quit = true;
  } catch (const InputError& e) {
    throw InputError(e.file, e.where, e.expected + " (script line " + std::to_string(c.line) + ", " + c.name + ")");
  } catch (const RunError& e) {
    throw RunError(std::string(e.what()) + " (script line " + std::to_string(c.line) + ", " + c.name + ")");
  }
  return refused;
}

// The frame just drawn into the files asked for: this frame's screenshot (shot), the run's
// last one (--screenshot), the recording's next frame. Headless, a screenshot that cannot be
// written ends the run; with a person watching, the mill keeps running and the panel says why.
void capture_frame(const ViewRequest& req, const ViewHooks& hooks, bool headless, bool last_frame,
                   const std::string& shot, int fw, int fh, UiState& ui) {
  if (shot.empty() && !(last_frame && !req.screenshot.empty()) && !ui.recording) return;
  const std::vector<std::uint8_t> px = read_window(fw, fh);
  if (!shot.empty()) {
    try {
      check_screenshot(shot, ui.inputs, "");
      write_png(shot, fw, fh, px);
      ui.message = "wrote " + shot;
    } catch (const std::exception& x) {
      if (headless) throw;
      ui.message = x.what();
    }
    if (hooks.notice) hooks.notice(ui.message);
  }
  if (last_frame && !req.screenshot.empty()) {
    check_screenshot(req.screenshot, ui.inputs, "--screenshot");
    write_png(req.screenshot, fw, fh, px);
  }
  if (ui.recording) {
    fs::create_directories(ui.record_to);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", ui.record_index++);
    write_png((fs::path(ui.record_to) / name).string(), fw, fh, px);
  }
}

// The mill and the panel drawn into a frame of fw x fh pixels; the panel's buttons leave
// their actions, run after the frame is shown.
void draw_frame(LiveMill& live, UiState& ui, int fw, int fh, double fps, double ratio,
                std::vector<std::function<void()>>& actions) {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  const float side = static_cast<float>(std::min(fh, fw));
  const Pane pane{0.5f * side, 0.5f * side, static_cast<float>(0.45 * side / live.scene().radius_m())};
  const WearView wear = live.wear_view();
  draw_mill(live, wear, wear.running, pane, ui.colour_by_speed);
  draw_panel(live, ui, side, static_cast<float>(fw) - side, static_cast<float>(fh), fps, ratio, wear, actions);
  ImGui::Render();
  glViewport(0, 0, fw, fh);
  glClearColor(22 / 255.0f, 22 / 255.0f, 26 / 255.0f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

}  // namespace

ViewOutcome run_view(const ViewRequest& req, const ViewHooks& hooks) {
  // Everything the run reads is checked before a window opens.
  std::vector<ScriptCommand> script;
  if (!req.script.empty()) script = read_script(req.script);
  std::vector<RunInput> inputs{{req.scene_file, "the scene on screen"}};
  if (!req.script.empty()) inputs.push_back({req.script, "the script being run"});
  if (!req.screenshot.empty()) check_screenshot(req.screenshot, inputs, "--screenshot");
  LiveMill live(req.scene_file, req.fidelity);
  const bool headless = req.frames > 0 || !req.script.empty();
  ViewWindow window(req.width, req.height, "millwear view: " + live.scene().name, headless);

  UiState ui;
  ui.inputs = std::move(inputs);
  sync_ui(ui, live);
  ui.shipped_profiles = profiles_beside(live.profile_file());
  ViewOutcome out;
  out.scene_name = live.scene().name;
  std::size_t next_command = 0;
  const auto t0 = Clock::now();
  auto last = t0;
  double fps = 0.0, ratio = 0.0;
  const double clock0 = live.clock_s();
  bool quit = false;
  while (!glfwWindowShouldClose(window.get())) {
    glfwPollEvents();
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window.get(), &fw, &fh);
    // Script commands due at this time, before the frame advances. Script time is the
    // frames' time (1/60 s a frame), so a paused mill or a running wear history does not
    // hold the script up.
    std::string shot = ui.shot_pending;
    ui.shot_pending.clear();
    const double script_clock = static_cast<double>(out.frames) * kFrameSimS;
    // One screenshot a frame, of the state the lines before it left: the lines after a
    // `screenshot` (another screenshot among them) run from the next frame on.
    while (out.refused == 0 && next_command < script.size() && script[next_command].time_s <= script_clock + 1e-9) {
      if (script[next_command].name == "screenshot" && !shot.empty()) break;
      const ScriptCommand& c = script[next_command++];
      const std::string refused = run_script_command(c, live, ui, hooks, shot, quit);
      if (!refused.empty()) {
        ++out.refused;
        ui.message = refused;
        if (hooks.notice) hooks.notice("refused at line " + std::to_string(c.line) + ": " + refused);
      }
      sync_ui(ui, live);
      if (c.name == "screenshot") break;
    }
    if (out.refused > 0) {
      // A refused control ends the run at its line: the screenshot a line before it asked for
      // at this time is taken, and nothing more is written (no recorded frame, no --screenshot).
      ui.recording = false;
      std::vector<std::function<void()>> ignored;
      draw_frame(live, ui, fw, fh, fps, ratio, ignored);
      capture_frame(req, hooks, headless, false, shot, fw, fh, ui);
      break;
    }
    const auto now = Clock::now();
    const double wall_dt = std::chrono::duration<double>(now - last).count();
    last = now;
    const double before = live.clock_s();
    const auto physics0 = Clock::now();
    // With a person watching, the mill advances by the wall time since the last frame, so it
    // keeps real time while frames draw slowly (software OpenGL, a projector's large window)
    // down to kSlowestFrameS; headless, a fixed 1/60 s per frame, the same on any machine.
    if (!quit) live.advance(headless ? kFrameSimS : std::min(wall_dt, kSlowestFrameS));
    out.physics_wall_s += std::chrono::duration<double>(Clock::now() - physics0).count();
    if (wall_dt > 0) {
      fps = 0.9 * fps + 0.1 / wall_dt;
      ratio = 0.9 * ratio + 0.1 * (live.clock_s() - before) / wall_dt;
    }
    if (ui.trails != static_cast<int>(live.trails().size()) && live.trails().size() > 0) ui.trails = static_cast<int>(live.trails().size());

    std::vector<std::function<void()>> actions;
    draw_frame(live, ui, fw, fh, fps, ratio, actions);
    ++out.frames;
    // A `quit` ends the run after this frame (its screenshots and recording included).
    const bool last_frame = quit || (req.frames > 0 && out.frames >= req.frames);
    capture_frame(req, hooks, headless, last_frame, shot, fw, fh, ui);
    glfwSwapBuffers(window.get());
    for (auto& a : actions) a();
    if (last_frame) break;
  }
  out.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  out.simulated_s = live.clock_s() - clock0;
  out.disks = live.active_disks();
  out.lost_disks = live.lost_disks();
  live.stop_wear();
  return out;
}

}  // namespace millwear::view
