// Killing a run of rockcal (SIGKILL) at a chosen moment, and comparing its
// output folder, once resumed to the end, with that of a run that was not
// killed, wall times aside: for the kill and resume tests of calibrate
// (calibrate_kill_heavy_test.cc) and of a campaign's posterior
// (campaign_posterior_kill_heavy_test.cc).
#ifndef ROCKCAL_TESTS_CLI_KILL_FIXTURE_H_
#define ROCKCAL_TESTS_CLI_KILL_FIXTURE_H_

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_fixture.h"

namespace rockcal::cli::testing {

namespace kill_fs = std::filesystem;

// Wall-clock time as the file system stamps it.
inline timespec Now() {
  timespec t{};
  ::clock_gettime(CLOCK_REALTIME, &t);
  return t;
}

// True when `path` exists and was last written at or after `since`.
inline bool WrittenSince(const std::string& path, const timespec& since) {
  struct stat s {};
  if (::stat(path.c_str(), &s) != 0) return false;
  return s.st_mtim.tv_sec > since.tv_sec ||
         (s.st_mtim.tv_sec == since.tv_sec && s.st_mtim.tv_nsec >= since.tv_nsec);
}

// When to kill a run: after `delay` seconds; as soon as `file` (in the
// output folder) is written or its temporary is there ("" = the folder
// itself); or as soon as `file` holds `text`.
struct KillPoint {
  enum class Kind { kAfter, kWritten, kHolds } kind = Kind::kAfter;
  double delay = 0.0;
  std::string file;
  std::string text;  // kHolds

  static KillPoint After(double seconds) { return {Kind::kAfter, seconds, "", ""}; }
  static KillPoint Written(const std::string& file) { return {Kind::kWritten, 0.0, file, ""}; }
  static KillPoint Holds(const std::string& file, const std::string& text) {
    return {Kind::kHolds, 0.0, file, text};
  }

  std::string Describe() const {
    std::ostringstream s;
    if (kind == Kind::kAfter)
      s << "after " << delay << " s";
    else if (kind == Kind::kHolds)
      s << "when " << file << " holds '" << text << "'";
    else
      s << "when " << (file.empty() ? std::string("the output folder") : file) << " is written";
    return s.str();
  }
};

// The command line of `args` (an argv: the executable first) without the executable.
inline std::string Joined(const std::vector<std::string>& args) {
  std::string s;
  for (std::size_t k = 1; k < args.size(); ++k) s += (k > 1 ? " " : "") + args[k];
  return s;
}

struct Outcome {
  bool killed = false;
  int status = -1;  // exit status when it was not killed
  std::string output;
};

// Runs `args` with output into `log`, and kills it (SIGKILL) at `point`
// unless it exits before.
inline Outcome RunAndKill(const std::vector<std::string>& args, const std::string& out,
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
    } else if (point.kind == KillPoint::Kind::kHolds) {
      now = ReadFile(out + "/" + point.file).find(point.text) != std::string::npos;
    } else if (point.file.empty()) {
      std::error_code ec;
      now = kill_fs::exists(out, ec);
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
inline bool RunOnly(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  if (n == "dt_seconds" || n == "sample_seconds") return false;
  return n.find("seconds") != std::string::npos || n.find("wall") != std::string::npos ||
         n.find("elapsed") != std::string::npos || n == "simulated" || n == "replayed";
}

inline nlohmann::json StripJson(const nlohmann::json& j) {
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

inline std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

inline std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

// The CSV without its run-only columns (the values have no quoted commas).
inline std::string StripCsv(const std::string& text) {
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

inline bool NumberChar(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == 'e' || c == 'E' ||
         c == '+' || c == '-';
}

// Replaces the number that ends just before each `marker` with X.
inline void MaskNumberBefore(std::string* text, const std::string& marker) {
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
inline std::string StripText(std::string text) {
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
inline std::string StripHtml(std::string text) {
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

inline std::string Normalised(const std::string& path) {
  const std::string text = ReadFile(path);
  const std::string ext = kill_fs::path(path).extension().string();
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

// The files under `dir`, by their path relative to it.
inline std::set<std::string> FileNames(const std::string& dir) {
  std::set<std::string> names;
  std::error_code ec;
  for (kill_fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (!it->is_directory(ec)) names.insert(kill_fs::relative(it->path(), dir, ec).string());
  return names;
}

// Every difference of `dir` from `reference`: files missing or extra, and
// files whose normalised text differs. The lock file's text is not a result:
// it names the run that held the folder, so a run killed after its last
// output leaves its name there where a run that ended leaves it empty.
inline std::vector<std::string> Differences(const std::string& reference, const std::string& dir) {
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

inline std::string List(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : "; ") + i;
  return s;
}

}  // namespace rockcal::cli::testing

#endif  // ROCKCAL_TESTS_CLI_KILL_FIXTURE_H_
