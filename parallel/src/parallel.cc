// Replicated control over the ranks of a job: the rocks of a simulation in
// blocks, a list of tasks as a queue, and rank 0's decisions and errors
// shared by every rank. The messages themselves are transport.h's.
#include "rockcal/parallel/parallel.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "rockcal/core/error.h"
#include "transport.h"

namespace rockcal::parallel {
namespace {

using Clock = std::chrono::steady_clock;

// Message tags.
constexpr int kTaskTag = 1;    // rank 0 -> worker: a task index, -1 for "no more"
constexpr int kResultTag = 2;  // worker -> rank 0: the index and the task's outcome
constexpr int kBlockTag = 3;   // rank -> rank 0: a block of a simulation

bool in_task = false;            // within a Map task: everything runs on this rank
double longest_local = 0.0;      // seconds of the longest simulation or task run here
std::string scratch;             // ScratchFolder, once made

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The outcome of a piece of work on one rank, as bytes: status 0 (done,
// then the payload), 1 (an InputError: where, detail) or 2 (another error:
// its message).
std::string Outcome(const std::function<std::string()>& work) {
  Writer w;
  try {
    std::string payload = work();
    w.Int(0);
    w.String(payload);
  } catch (const InputError& e) {
    w.Int(1);
    w.String(e.where());
    w.String(e.detail());
  } catch (const std::exception& e) {
    w.Int(2);
    w.String(e.what());
  }
  return w.bytes();
}

// The payload of an Outcome; throws its error.
std::string Payload(const std::string& outcome) {
  Reader r(outcome);
  const long long status = r.Int();
  if (status == 0) return r.String();
  if (status == 1) {
    std::string where = r.String();
    std::string detail = r.String();
    throw InputError(where, detail);
  }
  throw std::runtime_error(r.String());
}

// Rocks [first, last) of block `b` of `blocks` over `total` rocks.
std::pair<int, int> Block(int total, int blocks, int b) {
  const long long t = total;
  return {static_cast<int>(t * b / blocks), static_cast<int>(t * (b + 1) / blocks)};
}

void Note(double seconds) { longest_local = std::max(longest_local, seconds); }

}  // namespace

Session::Session(int* argc, char*** argv) { transport::Init(argc, argv); }

Session::~Session() {
  if (!scratch.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(scratch, ignored);
  }
  transport::Finalize();
}

bool Available() { return transport::Available(); }
int Rank() { return transport::Rank(); }
int Size() { return transport::Size(); }
bool IsRoot() { return transport::Rank() == 0; }
std::string Host(int rank) { return transport::Host(rank); }

double RankTimeout() {
  if (const char* text = std::getenv("ROCKCAL_RANK_TIMEOUT")) {
    char* end = nullptr;
    const double s = std::strtod(text, &end);
    if (end != text && *end == '\0' && s > 0) return s;
  }
  return std::max(600.0, 20.0 * longest_local);
}

core::SimulationResult Simulate(const core::Scene& scene) {
  return parallel::Simulate(scene, core::BuildTerrain(scene));
}

core::SimulationResult Simulate(const core::Scene& scene, const core::Terrain& terrain,
                                const core::ProgressFn& progress) {
  const auto t0 = Clock::now();
  const int size = Size();
  if (size == 1 || in_task) {
    core::SimulationResult result = core::Simulate(scene, terrain, progress);
    Note(Since(t0));
    return result;
  }
  const int total = scene.total_rocks();
  // Named copies, not structured bindings: C++17 lambdas cannot capture
  // those (clang rejects it; the fuzz build uses clang).
  const std::pair<int, int> block = Block(total, size, Rank());
  const int first = block.first, last = block.second;
  core::ProgressFn scaled;
  if (progress && last > first)
    scaled = [&, n = last - first](int done, int) {
      progress(std::min(total, static_cast<int>(static_cast<long long>(done) * total / n)), total);
    };
  const std::string mine = Outcome([&] {
    return EncodeResult(core::SimulateRocks(scene, terrain, first, last, scaled));
  });
  Note(Since(t0));
  // The blocks to rank 0, in rank order; the joined result back to all.
  std::string joined;
  if (IsRoot()) {
    std::vector<std::string> outcomes(static_cast<std::size_t>(size));
    outcomes[0] = mine;
    for (int r = 1; r < size; ++r)
      outcomes[static_cast<std::size_t>(r)] =
          transport::Receive(r, kBlockTag, RankTimeout(), nullptr, [r] {
            return "rank " + std::to_string(r) + " (host " + Host(r) +
                   ") simulating its block of rocks";
          });
    joined = Outcome([&] {
      std::vector<core::SimulationResult> blocks;
      for (const std::string& o : outcomes) blocks.push_back(DecodeResult(Payload(o)));
      return EncodeResult(core::JoinRockBlocks(std::move(blocks)));
    });
  } else {
    transport::Send(0, kBlockTag, mine);
  }
  joined = transport::Broadcast(joined, RankTimeout());
  core::SimulationResult result = DecodeResult(Payload(joined));
  result.wall_seconds = Since(t0);
  return result;
}

namespace {

// Rank 0's side of Map under mpirun: hands the tasks out, two in hand per
// worker (one to run, one to start on at once while rank 0, busy with a
// task of its own, has not yet answered), runs tasks itself while none is
// back, and collects the outcomes into *outcomes, reporting each; then
// tells the workers to stop. Returns the outcomes packed for the broadcast.
std::string HandOutTasks(int count, const std::function<std::string(int)>& run,
                         const std::function<void(int)>& report,
                         std::vector<std::string>* outcomes) {
  const int size = Size();
  std::vector<int> outstanding(static_cast<std::size_t>(size), 0);
  int next = 0, finished = 0;
  auto give = [&](int worker) {
    Writer w;
    w.Int(next);
    transport::Send(worker, kTaskTag, w.bytes());
    ++outstanding[static_cast<std::size_t>(worker)];
    ++next;
  };
  for (int round = 0; round < 2; ++round)
    for (int w = 1; w < size && next < count; ++w) give(w);
  auto take = [&](int source, const std::string& message) {
    Reader r(message);
    const int index = static_cast<int>(r.Int());
    if (index < 0 || index >= count) transport::Fail("a malformed task result");
    (*outcomes)[static_cast<std::size_t>(index)] = r.String();
    --outstanding[static_cast<std::size_t>(source)];
    ++finished;
    if (next < count) give(source);
    report(index);
  };
  while (finished < count) {
    int source = 0;
    std::string message;
    while (transport::TryReceive(kResultTag, &source, &message)) take(source, message);
    if (finished >= count) break;
    if (next < count) {
      const int index = next++;
      (*outcomes)[static_cast<std::size_t>(index)] = run(index);
      ++finished;
      report(index);
      continue;
    }
    message = transport::Receive(-1, kResultTag, RankTimeout(), &source, [&] {
      std::string who;
      for (int w = 1; w < size; ++w)
        if (outstanding[static_cast<std::size_t>(w)] > 0)
          who += (who.empty() ? "" : ", ") + std::string("rank ") + std::to_string(w) + " (host " +
                 Host(w) + ")";
      return who + " running its tasks";
    });
    take(source, message);
  }
  for (int w = 1; w < size; ++w) {
    Writer stop;
    stop.Int(-1);
    transport::Send(w, kTaskTag, stop.bytes());
  }
  Writer w;
  for (const std::string& o : *outcomes) w.String(o);
  return w.bytes();
}

// A worker's side of Map: runs the tasks rank 0 sends, each outcome sent
// back with its index, until rank 0 says stop.
void ServeTasks(const std::function<std::string(int)>& run) {
  for (;;) {
    Reader r(transport::Receive(0, kTaskTag, RankTimeout(), nullptr,
                                [] { return "rank 0 (host " + Host(0) + ") handing out tasks"; }));
    const int index = static_cast<int>(r.Int());
    if (index < 0) break;
    Writer w;
    w.Int(index);
    w.String(run(index));
    transport::Send(0, kResultTag, w.bytes());
  }
}

}  // namespace

std::vector<std::string> Map(int count, const std::function<std::string(int)>& task,
                             const std::function<void(int, const std::string&)>& done) {
  std::vector<std::string> outcomes(static_cast<std::size_t>(std::max(count, 0)));
  const std::function<std::string(int)> run = [&](int index) {
    const auto t0 = Clock::now();
    const bool outer = in_task;
    in_task = true;
    std::string outcome = Outcome([&] { return task(index); });
    in_task = outer;
    Note(Since(t0));
    return outcome;
  };
  const std::function<void(int)> report = [&](int index) {
    if (!done) return;
    const std::string& o = outcomes[static_cast<std::size_t>(index)];
    Reader r(o);
    done(index, r.Int() == 0 ? r.String() : std::string());
  };
  if (Size() == 1 || in_task) {
    for (int k = 0; k < count; ++k) {
      outcomes[static_cast<std::size_t>(k)] = run(k);
      report(k);
    }
  } else {
    std::string all;
    if (IsRoot())
      all = HandOutTasks(count, run, report, &outcomes);
    else
      ServeTasks(run);
    all = transport::Broadcast(all, RankTimeout());
    Reader r(all);
    for (std::string& o : outcomes) o = r.String();
  }
  // The first failing task's error, on every rank alike.
  std::vector<std::string> results;
  results.reserve(outcomes.size());
  for (const std::string& o : outcomes) results.push_back(Payload(o));
  return results;
}

bool RootDecides(bool value) {
  if (Size() == 1 || in_task) return value;
  const std::string bytes = transport::Broadcast(std::string(1, value ? '1' : '0'), RankTimeout());
  return bytes == "1";
}

void OnRoot(const std::function<void()>& work) {
  if (Size() == 1 || in_task) {
    work();
    return;
  }
  std::string outcome;
  if (IsRoot())
    outcome = Outcome([&] {
      work();
      return std::string();
    });
  Payload(transport::Broadcast(outcome, RankTimeout()));
}

void ShareFiles(const std::string& folder, const std::function<bool(const std::string&)>& wanted,
                const std::string& into) {
  if (Size() == 1 || in_task) return;
  std::string files;
  if (IsRoot()) {
    Writer w;
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
      if (entry.is_regular_file(ec) && wanted(entry.path().filename().string()))
        names.push_back(entry.path().filename().string());
    std::sort(names.begin(), names.end());
    for (const std::string& name : names) {
      std::ifstream in(folder + "/" + name, std::ios::binary);
      if (!in) continue;
      std::stringstream text;
      text << in.rdbuf();
      w.String(name);
      w.String(text.str());
    }
    files = w.bytes();
  }
  files = transport::Broadcast(files, RankTimeout());
  if (IsRoot()) return;
  Reader r(files);
  while (!r.done()) {
    const std::string name = r.String();
    const std::string text = r.String();
    std::ofstream out(into + "/" + name, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out.flush())
      transport::Fail("rank " + std::to_string(Rank()) + " (host " + Host(Rank()) +
                      "): cannot write " + into + "/" + name);
  }
}

std::string ScratchFolder() {
  if (scratch.empty()) {
    const char* tmp = std::getenv("TMPDIR");
    const std::string base = tmp && *tmp ? tmp : "/tmp";
    const std::string path = base + "/rockcal-rank" + std::to_string(Rank()) + "-" +
                             std::to_string(::getpid());
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (ec)
      transport::Fail("rank " + std::to_string(Rank()) + " (host " + Host(Rank()) +
                      "): cannot create " + path + ": " + ec.message());
    scratch = path;
  }
  return scratch;
}

}  // namespace rockcal::parallel
