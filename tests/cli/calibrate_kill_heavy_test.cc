// Kill anywhere: a calibration killed (SIGKILL) at seeded random moments, while
// it starts, searches or writes its final files, and then resumed with
// --resume ends in a complete folder whose results are those of an
// uninterrupted run, wall times aside (issue 14). ROCKCAL_KILL_SEED=S replays
// another set of kill moments. Labelled heavy: it runs rockcal some twenty
// times, 20-30 s in the optimised build but many minutes under the sanitizers.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iterator>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_fixture.h"

namespace rockcal::cli {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadFile;
using testing::Rockcal;
using testing::RunResult;

// The files a finished calibration of the tutorial writes after its search,
// calibration.json last: the targets of the kills "during the final writes".
const std::vector<std::string> kFinalFiles = {
    "summary.json", "rocks.csv",      "diagnostics.json", "parameters.json", "parameters.csv",
    "parameters.md", "trace.csv",     "reach.json",       "report.html",      "calibration.json"};

std::vector<std::string> CalibrateArgs(const std::string& out, bool resume) {
  const std::string tutorial = std::string(ROCKCAL_SOURCE_DIR) + "/sites/examples/tutorial";
  std::vector<std::string> args = {ROCKCAL_EXE,     "calibrate",
                                   tutorial + "/site.json", "--observations",
                                   tutorial + "/observations.json",
                                   "--rocks",       "4",
                                   "--seed",        "2",
                                   "--max-evals",   "6",
                                   "--reach",       "4",
                                   "--quiet",       "--out",
                                   out};
  if (resume) args.push_back("--resume");
  return args;
}

std::string Joined(const std::vector<std::string>& args) {
  std::string s;
  for (std::size_t k = 1; k < args.size(); ++k) s += (k > 1 ? " " : "") + args[k];
  return s;
}

// Wall-clock time as the file system stamps it.
timespec Now() {
  timespec t{};
  ::clock_gettime(CLOCK_REALTIME, &t);
  return t;
}

// True when `path` exists and was last written at or after `since`.
bool WrittenSince(const std::string& path, const timespec& since) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) return false;
  return s.st_mtim.tv_sec > since.tv_sec ||
         (s.st_mtim.tv_sec == since.tv_sec && s.st_mtim.tv_nsec >= since.tv_nsec);
}

// When to kill a run: after `delay` seconds, or as soon as `file` (in the
// output folder) is written or its temporary is there; "" = the folder itself.
struct KillPoint {
  enum class Kind { kAfter, kWritten } kind = Kind::kAfter;
  double delay = 0.0;
  std::string file;

  std::string Describe() const {
    std::ostringstream s;
    if (kind == Kind::kAfter)
      s << "after " << delay << " s";
    else
      s << "when " << (file.empty() ? std::string("the output folder") : file) << " is written";
    return s.str();
  }
};

struct Outcome {
  bool killed = false;
  int status = -1;  // exit status when it was not killed
  std::string output;
};

// Runs `args` with output into `log`, and kills it (SIGKILL) at `point`
// unless it exits before.
Outcome RunAndKill(const std::vector<std::string>& args, const std::string& out,
                   const KillPoint& point, const std::string& log) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  // A file the previous run wrote must not look fresh to the kill below.
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const timespec since = Now();
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, 1);
      ::dup2(fd, 2);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  Outcome outcome;
  const std::string temp_suffix = ".tmp-" + std::to_string(pid);
  for (;;) {
    int raw = 0;
    if (::waitpid(pid, &raw, WNOHANG) == pid) {
      outcome.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
      break;
    }
    bool now = false;
    if (point.kind == KillPoint::Kind::kAfter) {
      now = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >=
            point.delay;
    } else if (point.file.empty()) {
      std::error_code ec;
      now = fs::exists(out, ec);
    } else {
      const std::string path = out + "/" + point.file;
      now = WrittenSince(path, since) || ::access((path + temp_suffix).c_str(), F_OK) == 0;
    }
    if (now) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &raw, 0);
      outcome.killed = WIFSIGNALED(raw) && WTERMSIG(raw) == SIGKILL;
      if (!outcome.killed) outcome.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
      break;
    }
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  outcome.output = ReadFile(log);
  return outcome;
}

// --- Comparing two folders, wall times aside --------------------------------

// A key or column that names wall time (tests/golden/normalise.py's rule), or
// "simulated" / "replayed": how many evaluations this run computed rather than
// took from the log, which a resume changes by design.
bool RunOnly(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  if (n == "dt_seconds" || n == "sample_seconds") return false;
  return n.find("seconds") != std::string::npos || n.find("wall") != std::string::npos ||
         n.find("elapsed") != std::string::npos || n == "simulated" || n == "replayed";
}

nlohmann::json StripJson(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, value] : j.items())
      if (!RunOnly(key)) out[key] = StripJson(value);
    return out;
  }
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& value : j) out.push_back(StripJson(value));
    return out;
  }
  return j;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// The CSV without its run-only columns (the values have no quoted commas).
std::string StripCsv(const std::string& text) {
  const std::vector<std::string> lines = Lines(text);
  if (lines.empty()) return text;
  std::vector<bool> keep;
  for (const std::string& h : Cells(lines[0])) keep.push_back(!RunOnly(h));
  std::string out;
  for (const std::string& line : lines) {
    const std::vector<std::string> cells = Cells(line);
    for (std::size_t k = 0; k < cells.size(); ++k)
      if (k >= keep.size() || keep[k]) out += cells[k] + ",";
    out += "\n";
  }
  return out;
}

bool NumberChar(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == 'E' ||
         c == '+' || c == '-';
}

// Replaces the number that ends just before each `marker` with X.
void MaskNumberBefore(std::string* text, const std::string& marker) {
  for (std::size_t at = text->find(marker); at != std::string::npos;
       at = text->find(marker, at + 1)) {
    std::size_t begin = at;
    while (begin > 0 && NumberChar((*text)[begin - 1])) --begin;
    if (begin == at) continue;
    text->replace(begin, at - begin, "X");
    at = begin + 1;
  }
}

// Markdown or HTML text without its wall times ("in 0.7 s", "0.07 s wall
// time") and its count of simulated evaluations.
std::string StripText(std::string text) {
  MaskNumberBefore(&text, " s wall time");
  MaskNumberBefore(&text, " simulated, the rest replayed");
  for (std::size_t at = text.find("in "); at != std::string::npos; at = text.find("in ", at + 1)) {
    std::size_t end = at + 3;
    while (end < text.size() && NumberChar(text[end])) ++end;
    if (end == at + 3 || text.compare(end, 2, " s") != 0) continue;
    if (end + 2 < text.size() && std::isalnum(static_cast<unsigned char>(text[end + 2]))) continue;
    text.replace(at + 3, end - at - 3, "X");
  }
  return text;
}

// The report as StripText leaves it, without the values bound to wall-time
// keys and the plot of the misfit against wall time.
std::string StripHtml(std::string text) {
  const std::size_t title = text.find("<title>Misfit against wall time</title>");
  if (title != std::string::npos) {
    const std::size_t begin = text.rfind("<svg", title);
    const std::size_t end = text.find("</svg>", title);
    if (begin != std::string::npos && end != std::string::npos)
      text.replace(begin, end + 6 - begin, "<svg>misfit against wall time</svg>");
  }
  // data-json="file#/key" data-value="V">V</span>
  const std::string bound = "data-json=\"";
  for (std::size_t at = text.find(bound); at != std::string::npos; at = text.find(bound, at + 1)) {
    const std::size_t key_end = text.find('"', at + bound.size());
    if (key_end == std::string::npos) break;
    const std::string key = text.substr(at + bound.size(), key_end - at - bound.size());
    const std::size_t last = key.find_last_of("#/");
    if (last == std::string::npos || !RunOnly(key.substr(last + 1))) continue;
    const std::string value = " data-value=\"";
    if (text.compare(key_end + 1, value.size(), value) != 0) continue;
    const std::size_t v = key_end + 1 + value.size();
    const std::size_t v_end = text.find("\">", v);
    const std::size_t shown_end = text.find('<', v_end);
    if (v_end == std::string::npos || shown_end == std::string::npos) break;
    text.replace(v, shown_end - v, "X\">X");
  }
  return StripText(text);
}

std::string Normalised(const std::string& path) {
  const std::string text = ReadFile(path);
  const std::string ext = fs::path(path).extension().string();
  try {
    if (ext == ".json") return StripJson(nlohmann::json::parse(text)).dump(1);
    if (ext == ".jsonl") {
      std::string out;
      for (const std::string& line : Lines(text))
        if (!line.empty()) out += StripJson(nlohmann::json::parse(line)).dump() + "\n";
      return out;
    }
  } catch (const nlohmann::json::exception& e) {
    return "unreadable JSON: " + std::string(e.what());
  }
  if (ext == ".csv") return StripCsv(text);
  if (ext == ".html") return StripHtml(text);
  if (ext == ".md") return StripText(text);
  return text;
}

std::set<std::string> FileNames(const std::string& dir) {
  std::set<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    names.insert(it->path().filename().string());
  return names;
}

// Every difference of `dir` from `reference`: files missing or extra, and
// files whose normalised text differs. The lock file's text is not a result:
// it names the run that held the folder, so a run killed after its last
// output leaves its name there where a run that ended leaves it empty.
std::vector<std::string> Differences(const std::string& reference, const std::string& dir) {
  std::vector<std::string> out;
  const std::set<std::string> want = FileNames(reference), have = FileNames(dir);
  for (const std::string& f : want)
    if (!have.count(f)) out.push_back("missing " + f);
  for (const std::string& f : have)
    if (!want.count(f)) out.push_back("extra " + f);
  for (const std::string& f : want)
    if (f != ".rockcal-lock" /* reports::kOutputLock */ && have.count(f) &&
        Normalised(reference + "/" + f) != Normalised(dir + "/" + f))
      out.push_back("differs " + f);
  return out;
}

std::string List(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : "; ") + i;
  return s;
}

// --- The test ----------------------------------------------------------------

TEST(CalibrateKill, KilledAnywhereResumesToTheUninterruptedResult) {
  unsigned seed = 14;
  if (const char* s = std::getenv("ROCKCAL_KILL_SEED")) seed = static_cast<unsigned>(std::atoi(s));
  std::mt19937 rng(seed);
  const std::string work = FreshDir("work");
  fs::create_directories(work);
  const std::string log = work + "/run.log";

  // The uninterrupted run, and how long it takes here.
  const std::string reference = work + "/reference";
  const auto t0 = std::chrono::steady_clock::now();
  const Outcome straight = RunAndKill(CalibrateArgs(reference, false), reference,
                                      {KillPoint::Kind::kAfter, 1e9, ""}, log);
  const double run_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_EQ(straight.status, 0) << straight.output;
  for (const std::string& f : kFinalFiles) ASSERT_TRUE(fs::exists(reference + "/" + f)) << f;

  // Each case kills a calibration once or twice (the first run, then its
  // resume) and lets a last resume finish. The kill points: the folder's
  // appearance, the log's, four of the final files (calibration.json always)
  // and, in a third of the kills, a random moment of a run.
  std::vector<KillPoint> targets;
  targets.push_back({KillPoint::Kind::kWritten, 0.0, ""});
  targets.push_back({KillPoint::Kind::kWritten, 0.0, "evaluations.jsonl"});
  targets.push_back({KillPoint::Kind::kWritten, 0.0, "calibration.json"});
  std::vector<std::string> finals;
  std::sample(kFinalFiles.begin(), kFinalFiles.end() - 1, std::back_inserter(finals), 3, rng);
  for (const std::string& f : finals) targets.push_back({KillPoint::Kind::kWritten, 0.0, f});
  std::shuffle(targets.begin(), targets.end(), rng);
  std::uniform_real_distribution<double> moment(0.0, run_seconds);
  std::size_t next_target = 0;
  int kills = 0, cases = 0;
  while (next_target < targets.size()) {
    ++cases;
    const std::string out = work + "/case-" + std::to_string(cases);
    std::vector<KillPoint> plan;
    const int kills_in_case = 1 + static_cast<int>(rng() % 2);
    for (int k = 0; k < kills_in_case; ++k) {
      if (rng() % 3 == 0 || next_target >= targets.size())
        plan.push_back({KillPoint::Kind::kAfter, moment(rng), ""});
      else
        plan.push_back(targets[next_target++]);
    }
    std::string history = "seed " + std::to_string(seed) + ", case " + std::to_string(cases) +
                          " (rockcal " + Joined(CalibrateArgs(out, false)) + "):";
    for (const KillPoint& point : plan) {
      std::error_code ec;
      const bool resume = fs::exists(out, ec);  // a run killed before its folder starts afresh
      const std::vector<std::string> args = CalibrateArgs(out, resume);
      const Outcome o = RunAndKill(args, out, point, log);
      history += std::string(resume ? " resume" : " run") + " killed " + point.Describe() +
                 (o.killed ? "" : " (finished first, status " + std::to_string(o.status) + ")");
      if (o.killed) {
        history += ", leaving {";
        for (const std::string& f : FileNames(out)) history += " " + f;
        history += " };";
      }
      if (o.killed) ++kills;
      ASSERT_TRUE(o.killed || o.status == 0) << history << "\n" << o.output;
      // A folder that says it is finished (calibration.json) is finished.
      if (fs::exists(out + "/calibration.json", ec)) {
        EXPECT_EQ(List(Differences(reference, out)), "")
            << history << ": a folder with calibration.json must be complete";
      }
    }
    std::error_code ec;
    const bool resume = fs::exists(out, ec);
    const std::vector<std::string> args = CalibrateArgs(out, resume);
    const Outcome last = RunAndKill(args, out, {KillPoint::Kind::kAfter, 1e9, ""}, log);
    history += std::string(resume ? " resume" : " run") + " to the end.";
    ASSERT_EQ(last.status, 0) << history << "\n" << last.output;
    EXPECT_EQ(List(Differences(reference, out)), "") << history;
    const RunResult table = Rockcal("table " + out + " --quiet --out " + work + "/table-" +
                                    std::to_string(cases));
    EXPECT_EQ(table.status, 0) << history << "\n" << table.err;
    std::printf("%s\n", history.c_str());
    if (HasFailure()) break;
  }
  std::printf("kill test, seed %u: %d kills in %d cases; an uninterrupted run takes %.2f s\n", seed,
              kills, cases, run_seconds);
  EXPECT_GE(kills, static_cast<int>(targets.size()) / 2) << "most kill points should be reached";
}

}  // namespace
}  // namespace rockcal::cli
