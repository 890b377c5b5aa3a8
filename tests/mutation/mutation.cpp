// A mutation test of hostile input: every key of the shipped input files (scenes, profiles,
// comparison and screen files) and every column and row kind of the CSV inputs (surveys,
// hardness periods) is given hostile values (absent, wrong type, NaN, infinities, negative,
// zero, huge, tiny, long and control-character strings, CSV-breaking characters), and each
// mutated file is handed to the millwear program (validation first, then a short real run)
// under a time bound and a memory limit. Each case ends in one outcome class; a crash, a
// hang, an allocation blow-up or a wrong exit (exit 2 that names neither file nor key, or
// writes files; exit 0 with malformed, non-finite or empty results) fails the test.
//
//   millwear_mutation [-j N] [--sample N [--seed S]] [--only TEXT] [--report FILE] [--list]
//                     [--binary PATH] [--source DIR] [--work DIR] [--keep]
//                     [--timeout-check S] [--timeout-run S] [--memory-gb G]
//
// Exit codes: 0 no failing case; 1 some case failed; 2 bad command line; 3 the harness
// could not set up (e.g. the reference run for the survey files failed).
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <thread>

#include "cases.hpp"
#include "outcome.hpp"
#include "spawn.hpp"

#ifndef MILLWEAR_BINARY
#define MILLWEAR_BINARY ""
#endif
#ifndef MILLWEAR_SOURCE_DIR
#define MILLWEAR_SOURCE_DIR ""
#endif

namespace mutation {
namespace {

struct Options {
  std::string binary = MILLWEAR_BINARY;
  std::string source = MILLWEAR_SOURCE_DIR;
  std::string work;
  std::string only;
  std::string report;
  int jobs = 2;
  std::size_t sample = 0;  // 0: every case
  std::uint64_t seed = 1;
  bool list = false;
  bool keep = false;
  double timeout_check = 30.0;
  double timeout_run = 90.0;
  double memory_gb = 4.0;
};

struct Result {
  Outcome outcome = Outcome::Ok;
  std::string step;     // the command the outcome came from
  std::string detail;
  std::string message;  // first stderr line
  double wall_s = 0.0;
};

void usage() {
  std::fprintf(stderr,
               "usage: millwear_mutation [-j N] [--sample N [--seed S]] [--only TEXT] [--report FILE] [--list]\n"
               "                         [--binary PATH] [--source DIR] [--work DIR] [--keep]\n"
               "                         [--timeout-check S] [--timeout-run S] [--memory-gb G]\n");
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "-j" || a == "--jobs") o.jobs = std::max(1, std::stoi(next()));
      else if (a == "--sample") o.sample = std::stoul(next());
      else if (a == "--seed") o.seed = std::stoull(next());
      else if (a == "--only") o.only = next();
      else if (a == "--report") o.report = next();
      else if (a == "--binary") o.binary = next();
      else if (a == "--source") o.source = next();
      else if (a == "--work") o.work = next();
      else if (a == "--timeout-check") o.timeout_check = std::stod(next());
      else if (a == "--timeout-run") o.timeout_run = std::stod(next());
      else if (a == "--memory-gb") o.memory_gb = std::stod(next());
      else if (a == "--list") o.list = true;
      else if (a == "--keep") o.keep = true;
      else if (a == "-h" || a == "--help") { usage(); std::exit(0); }
      else { std::fprintf(stderr, "millwear_mutation: unknown option %s\n", a.c_str()); return false; }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "millwear_mutation: %s: %s\n", a.c_str(), e.what());
      return false;
    }
  }
  if (o.binary.empty() || o.source.empty()) {
    std::fprintf(stderr, "millwear_mutation: --binary and --source are needed (no build defaults)\n");
    return false;
  }
  return true;
}

// A fixed selection, the same on every platform: a Fisher-Yates shuffle driven by
// mt19937_64 (whose output the standard fixes) and plain modulo, then back in case order.
std::vector<std::size_t> sample_of(std::size_t n, std::size_t k, std::uint64_t seed) {
  std::vector<std::size_t> idx(n);
  for (std::size_t i = 0; i < n; ++i) idx[i] = i;
  std::mt19937_64 rng(seed);
  for (std::size_t i = n; i > 1; --i) std::swap(idx[i - 1], idx[rng() % i]);
  idx.resize(std::min(k, n));
  std::sort(idx.begin(), idx.end());
  return idx;
}

std::string one_line(std::string s, std::size_t n = 160) {
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  if (s.size() > n) s = s.substr(0, n) + "...";
  return s;
}

// The grouping key of a cause: array indices folded, so species[0] and species[1] group.
std::string fold_indices(const std::string& key) {
  std::string out;
  for (std::size_t i = 0; i < key.size(); ++i) {
    if (key[i] == '[') {
      const std::size_t j = key.find(']', i);
      if (j != std::string::npos) {
        out += "[*]";
        i = j;
        continue;
      }
    }
    out += key[i];
  }
  // CSV cells: the line does not make a different cause
  const std::size_t l = out.find(", line ");
  if (l != std::string::npos) out = out.substr(0, l);
  return out;
}

bool is_wear_key(const std::string& key) { return key.rfind("wear", 0) == 0; }

class Harness {
 public:
  Harness(Options o, std::vector<Source> sources) : o_(std::move(o)), sources_(std::move(sources)) {}

  void set_base_run(const fs::path& p) { base_run_ = p; }

  std::vector<Step> steps_for(const Case& c, const Staged& st, const fs::path& dir) const {
    const std::string bin = o_.binary;
    const std::string in = st.primary.string();
    auto out = [&](const char* n) { return dir / n; };
    auto check = [&](const std::string& scene, const fs::path& o) {
      Step s;
      s.name = "run --check";
      s.argv = {bin, "run", scene, "--check", "-o", o.string()};
      s.out_dir = o;
      s.validation_only = true;
      s.timeout_s = o_.timeout_check;
      return s;
    };
    auto charge = [&](const std::string& scene, const fs::path& o) {
      Step s;
      s.name = "charge";
      s.argv = {bin, "charge", scene, "-o", o.string(), "--fidelity", "draft", "--revolutions", "0.2"};
      s.out_dir = o;
      s.required = {{"charge_summary.csv", 10}, {"liner_work.csv", 1}};
      s.timeout_s = o_.timeout_run;
      return s;
    };
    auto short_run = [&](const std::string& scene, const fs::path& o, const char* stage) {
      Step s;
      s.name = std::string("run --stop-after-stage ") + stage;
      s.argv = {bin, "run", scene, "-o", o.string(), "--fidelity", "draft", "--stop-after-stage", stage,
                "--jobs", "1", "--quiet"};
      s.out_dir = o;
      s.interrupt_is_success = true;
      s.required = {{"summary.csv", 1}};
      s.timeout_s = o_.timeout_run;
      return s;
    };
    std::vector<Step> steps;
    switch (c.source->kind) {
      case Kind::Scene:
        steps.push_back(check(in, out("out-check")));
        // wear keys only matter to the wear history; the rest to the charge
        steps.push_back(is_wear_key(c.key) ? short_run(in, out("out-run"), "1") : charge(in, out("out-run")));
        break;
      case Kind::Profile: {
        Step p;
        p.name = "profile";
        p.argv = {bin, "profile", in, "--csv", out("out-profile").string()};
        p.out_dir = out("out-profile");
        p.validation_only = true;
        p.timeout_s = o_.timeout_check;
        steps.push_back(p);
        steps.push_back(check(st.host_scene.string(), out("out-check")));
        steps.push_back(charge(st.host_scene.string(), out("out-run")));
        break;
      }
      case Kind::Comparison:
        steps.push_back(check(in, out("out-check")));
        steps.push_back(short_run(in, out("out-run"), "1"));
        break;
      case Kind::Screen: {
        Step s;
        s.name = "screen --emit parallel";
        s.argv = {bin, "screen", in, "-o", out("out-screen").string(), "--emit", "parallel"};
        s.out_dir = out("out-screen");
        s.validation_only = true;
        s.required = {{"designs.csv", 1}};
        s.timeout_s = o_.timeout_check;
        steps.push_back(s);
        break;
      }
      case Kind::Survey: {
        Step s;
        s.name = "validate --from";
        s.argv = {bin, "validate", st.host_scene.string(), "--measured", in, "-o", out("out-validate").string(),
                  "--from", base_run_.string()};
        s.out_dir = out("out-validate");
        s.required = {{"validation.csv", 1}};
        s.timeout_s = o_.timeout_run;
        steps.push_back(s);
        break;
      }
      case Kind::Hardness: {
        Step s;
        s.name = "hardness";
        s.argv = {bin, "hardness", in, "-o", out("out-hardness").string()};
        s.out_dir = out("out-hardness");
        s.required = {{"hardness_fit.csv", 1}, {"hardness_periods.csv", 2}};
        s.timeout_s = o_.timeout_run;
        steps.push_back(s);
        break;
      }
    }
    return steps;
  }

  Result run_case(const Case& c, const fs::path& work) const {
    Result r;
    const fs::path dir = work / ("c" + std::to_string(c.id));
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir / "log");
    Staged st;
    try {
      st = stage_case(c, sources_, dir / "in");
    } catch (const std::exception& e) {
      r.outcome = Outcome::BadExit;
      r.step = "(staging)";
      r.detail = std::string("the harness could not write the case: ") + e.what();
      return r;
    }
    Expectation ex;
    ex.file_name = st.primary.filename().string();
    ex.locations = c.locations;
    ex.any_line = c.any_line;
    if (!st.host_scene.empty()) ex.other_files.push_back(st.host_scene.filename().string());
    for (const auto& e : fs::directory_iterator(dir / "in"))
      if (e.path() != st.primary && e.path() != st.host_scene) ex.other_files.push_back(e.path().filename().string());
    Limits lim;
    lim.address_space_bytes = static_cast<std::uint64_t>(o_.memory_gb * (1ull << 30));
    lim.file_bytes = 1ull << 30;
    int k = 0;
    for (const Step& s : steps_for(c, st, dir)) {
      lim.timeout_s = s.timeout_s;
      const std::vector<fs::path> before = files_under(dir, dir / "log");
      const Finished f = run_bounded(s.argv, (dir / "log" / ("step" + std::to_string(k++))).string(), lim);
      const Judged j = judge(s, f, ex, dir, before);
      r.outcome = j.outcome;
      r.step = s.name;
      r.detail = j.detail;
      r.message = j.message;
      r.wall_s += f.wall_s;
      if (j.outcome != Outcome::Ok) break;
    }
    if (!o_.keep) fs::remove_all(dir, ec);
    return r;
  }

  const Options& options() const { return o_; }
  const std::vector<Source>& sources() const { return sources_; }

 private:
  Options o_;
  std::vector<Source> sources_;
  fs::path base_run_;
};

// The finished run the survey files are validated against (--from), made once.
bool make_base_run(const Harness& h, const fs::path& work, fs::path* run_dir) {
  const fs::path in = work / "base" / "in";
  const fs::path scene = stage_survey_scene(h.sources(), in);
  *run_dir = work / "base" / "run";
  fs::create_directories(work / "base" / "log");
  Limits lim;
  lim.timeout_s = 10 * h.options().timeout_run;
  const Finished f = run_bounded({h.options().binary, "run", scene.string(), "-o", run_dir->string(), "--quiet",
                                  "--jobs", std::to_string(h.options().jobs)},
                                 (work / "base" / "log" / "run").string(), lim);
  if (f.timed_out || f.signaled || f.exit_code != 0) {
    std::fprintf(stderr, "millwear_mutation: the reference run of %s failed (exit %d):\n%s\n", scene.c_str(),
                 f.exit_code, f.err.c_str());
    return false;
  }
  return true;
}

void print_report(const std::vector<const Case*>& cases, const std::vector<Result>& results, std::size_t full,
                  const Options& o, double wall) {
  std::map<Outcome, std::size_t> counts;
  for (const Result& r : results) ++counts[r.outcome];
  std::size_t failing = 0;
  for (const auto& [k, n] : counts)
    if (is_failure(k)) failing += n;
  std::printf("mutation test of hostile input: %zu case(s) of %zu in the full set, %d worker(s), %.0f s wall\n",
              cases.size(), full, o.jobs, wall);
  std::printf("  %-18s %7s\n", "outcome", "cases");
  for (Outcome k : {Outcome::Ok, Outcome::Refused, Outcome::RefusedElsewhere, Outcome::Event, Outcome::Signal,
                    Outcome::Hang, Outcome::Alloc, Outcome::BadExit})
    std::printf("  %-18s %7zu%s\n", outcome_name(k), counts[k], is_failure(k) ? "  (failure)" : "");
  std::printf("  %-18s %7zu\n", "failing", failing);

  // Baselines (the files as shipped) must pass; anything else means the harness is wrong.
  for (std::size_t i = 0; i < cases.size(); ++i)
    if (cases[i]->baseline && results[i].outcome != Outcome::Ok)
      std::printf("WARNING: the unmutated %s is %s at %s: %s | %s\n", cases[i]->source->rel.c_str(),
                  outcome_name(results[i].outcome), results[i].step.c_str(), results[i].detail.c_str(),
                  one_line(results[i].message).c_str());

  auto grouped = [&](bool failures, const char* title) {
    struct Group {
      std::size_t n = 0;
      std::vector<std::string> files;
      std::size_t example = 0;
    };
    std::map<std::string, Group> groups;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const Result& r = results[i];
      if (failures ? !is_failure(r.outcome) : r.outcome != Outcome::RefusedElsewhere) continue;
      const Case& c = *cases[i];
      const std::string g = std::string(outcome_name(r.outcome)) + " | " + r.step + " | " +
                            kind_name(c.source->kind) + " " + fold_indices(c.key) + " | " + c.value_class;
      Group& gr = groups[g];
      if (gr.n++ == 0) gr.example = i;
      if (std::find(gr.files.begin(), gr.files.end(), c.source->rel) == gr.files.end()) gr.files.push_back(c.source->rel);
    }
    if (groups.empty()) return;
    std::printf("\n%s (%zu group(s): outcome | command | kind key | value):\n", title, groups.size());
    for (const auto& [g, gr] : groups) {
      const Result& r = results[gr.example];
      std::string files;
      for (std::size_t k = 0; k < gr.files.size(); ++k) files += (k ? ", " : "") + gr.files[k];
      std::printf("  %s  x%zu  [%s]\n      %s | %s\n", g.c_str(), gr.n, files.c_str(), one_line(r.detail).c_str(),
                  one_line(r.message).c_str());
    }
  };
  grouped(false, "refused naming another key, line or file (not failures; listed to judge)");
  grouped(true, "failing cases by cause");

  if (failing) {
    std::printf("\nfailing cases (file | key | value | command | outcome | detail | first stderr line):\n");
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const Result& r = results[i];
      if (!is_failure(r.outcome)) continue;
      const Case& c = *cases[i];
      std::printf("  %s | %s | %s | %s | %s | %s | %s\n", c.source->rel.c_str(), one_line(c.key, 60).c_str(),
                  c.value_class.c_str(), r.step.c_str(), outcome_name(r.outcome), one_line(r.detail).c_str(),
                  one_line(r.message).c_str());
    }
  }
}

void write_tsv(const std::string& path, const std::vector<const Case*>& cases, const std::vector<Result>& results) {
  std::ofstream out(path);
  out << "id\tfile\tkind\tkey\tvalue\tcommand\toutcome\tfailure\twall_s\tdetail\tstderr\n";
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = *cases[i];
    const Result& r = results[i];
    auto clean = [](std::string s) {
      for (char& ch : s)
        if (ch == '\t' || static_cast<unsigned char>(ch) < 0x20) ch = ' ';
      return s;
    };
    out << c.id << '\t' << c.source->rel << '\t' << kind_name(c.source->kind) << '\t' << clean(one_line(c.key, 80))
        << '\t' << c.value_class << '\t' << r.step << '\t' << outcome_name(r.outcome) << '\t'
        << (is_failure(r.outcome) ? 1 : 0) << '\t' << r.wall_s << '\t' << clean(r.detail) << '\t'
        << clean(one_line(r.message, 300)) << '\n';
  }
}

int main_impl(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    usage();
    return 2;
  }
  std::vector<Source> sources = discover_sources(o.source);
  Harness h(o, std::move(sources));
  const std::vector<Case> all = build_cases(h.sources());

  std::vector<const Case*> selected;
  for (const Case& c : all) {
    const std::string text = c.source->rel + " " + c.key + " " + c.value_class;
    if (o.only.empty() || text.find(o.only) != std::string::npos) selected.push_back(&c);
  }
  if (o.sample > 0) {
    std::vector<const Case*> s;
    for (std::size_t i : sample_of(selected.size(), o.sample, o.seed)) s.push_back(selected[i]);
    selected = s;
  }
  if (o.list) {
    for (const Case* c : selected)
      std::printf("%zu\t%s\t%s\t%s\n", c->id, c->source->rel.c_str(), one_line(c->key, 80).c_str(),
                  c->value_class.c_str());
    std::printf("%zu case(s) of %zu\n", selected.size(), all.size());
    return 0;
  }

  fs::path work;
  const bool own_work = o.work.empty();
  if (own_work) {
    std::string tmpl = (fs::temp_directory_path() / "millwear-mutation-XXXXXX").string();
    if (!mkdtemp(&tmpl[0])) {
      std::perror("millwear_mutation: mkdtemp");
      return 3;
    }
    work = tmpl;
  } else {
    work = fs::absolute(o.work);
    fs::create_directories(work);
  }

  const auto t0 = std::chrono::steady_clock::now();
  if (std::any_of(selected.begin(), selected.end(), [](const Case* c) { return c->source->kind == Kind::Survey; })) {
    fs::path base;
    if (!make_base_run(h, work, &base)) return 3;
    h.set_base_run(base);
  }

  std::vector<Result> results(selected.size());
  std::atomic<std::size_t> next{0}, done{0}, failing{0};
  std::mutex print_mutex;
  auto worker = [&]() {
    for (;;) {
      const std::size_t i = next++;
      if (i >= selected.size()) return;
      results[i] = h.run_case(*selected[i], work);
      if (is_failure(results[i].outcome)) ++failing;
      const std::size_t d = ++done;
      if (d % 100 == 0 || d == selected.size()) {
        std::lock_guard<std::mutex> lock(print_mutex);
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::fprintf(stderr, "millwear_mutation: %zu/%zu cases, %zu failing, %.0f s\n", d, selected.size(),
                     failing.load(), el);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int k = 0; k < o.jobs; ++k) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  print_report(selected, results, all.size(), o, wall);
  if (!o.report.empty()) write_tsv(o.report, selected, results);
  if (own_work && !o.keep) {
    std::error_code ec;
    fs::remove_all(work, ec);
  }
  return failing > 0 ? 1 : 0;
}

}  // namespace
}  // namespace mutation

int main(int argc, char** argv) { return mutation::main_impl(argc, argv); }
