// The messages between ranks over MPI. Errors are returned, not fatal
// (MPI_ERRORS_RETURN), and every wait polls with a deadline, so that a rank
// that died or hangs is named instead of leaving the job waiting forever.
#include <fcntl.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <list>
#include <thread>
#include <vector>

#include "transport.h"

namespace rockcal::parallel::transport {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kBroadcastTag = 1000;  // above the callers' tags (transport.h)

bool started = false;  // MPI_Init was called (by us)
int rank = 0, size = 1;
std::vector<std::string> hosts = {"localhost"};
int terminal = 2;  // the stderr of the launcher, kept when a rank's own is silenced

struct PendingSend {
  std::string bytes;
  MPI_Request request = MPI_REQUEST_NULL;
  int to = 0;
};
std::list<PendingSend> pending;

std::string ErrorText(int code) {
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  return std::string(text, static_cast<std::size_t>(length));
}

void Check(int code, const std::string& what) {
  if (code != MPI_SUCCESS)
    Fail("rank " + std::to_string(rank) + " on " + Host(rank) + ": " + what + ": " +
         ErrorText(code));
}

std::string Who(int r) { return "rank " + std::to_string(r) + " (host " + Host(r) + ")"; }

// Completes the sends that can complete now.
void Progress() {
  for (auto it = pending.begin(); it != pending.end();) {
    int done = 0;
    Check(MPI_Test(&it->request, &done, MPI_STATUS_IGNORE), "sending to " + Who(it->to));
    it = done ? pending.erase(it) : std::next(it);
  }
}

// Polls `ready` until it is true or `timeout` seconds have passed; sleeps a
// little longer between polls as the wait goes on (a waiting rank leaves
// the cores to the ranks that compute).
template <typename Ready>
bool Await(double timeout, Ready ready) {
  const auto end = Clock::now() + std::chrono::duration<double>(timeout);
  auto pause = std::chrono::microseconds(20);
  for (;;) {
    Progress();
    if (ready()) return true;
    if (Clock::now() >= end) return false;
    std::this_thread::sleep_for(pause);
    pause = std::min(pause * 2, std::chrono::microseconds(2000));
  }
}

std::string Seconds(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f", s);
  return text;
}

bool LaunchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

}  // namespace

bool Available() { return true; }

void Init(int* argc, char*** argv) {
  if (!LaunchedByMpi()) return;
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
    std::fprintf(stderr, "rockcal: failed: MPI_Init failed\n");
    std::exit(1);
  }
  started = true;
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  char name[MPI_MAX_PROCESSOR_NAME] = {};
  int length = 0;
  MPI_Get_processor_name(name, &length);
  std::vector<char> all(static_cast<std::size_t>(size) * MPI_MAX_PROCESSOR_NAME, '\0');
  Check(MPI_Allgather(name, MPI_MAX_PROCESSOR_NAME, MPI_CHAR, all.data(), MPI_MAX_PROCESSOR_NAME,
                      MPI_CHAR, MPI_COMM_WORLD),
        "exchanging host names");
  hosts.clear();
  for (int r = 0; r < size; ++r)
    hosts.emplace_back(all.data() + static_cast<std::size_t>(r) * MPI_MAX_PROCESSOR_NAME);
  if (rank != 0) {
    // Only rank 0 prints; the others' reports of a failure still reach the
    // terminal through `terminal`.
    terminal = ::dup(2);
    const int null = ::open("/dev/null", O_WRONLY);
    if (null >= 0) {
      std::fflush(stdout);
      std::fflush(stderr);
      ::dup2(null, 1);
      ::dup2(null, 2);
      ::close(null);
    }
  }
}

void Finalize() {
  if (!started) return;
  Flush(60.0);
  MPI_Finalize();
  started = false;
}

int Rank() { return rank; }
int Size() { return size; }
std::string Host(int r) {
  return r >= 0 && r < static_cast<int>(hosts.size()) ? hosts[static_cast<std::size_t>(r)] : "?";
}

void Send(int to, int tag, std::string bytes) {
  if (bytes.size() > static_cast<std::size_t>(INT_MAX))
    Fail("a message of " + std::to_string(bytes.size()) + " bytes to " + Who(to) +
         " is beyond MPI's 2 GiB; spread the rocks over more simulations");
  pending.emplace_back();
  PendingSend& p = pending.back();
  p.bytes = std::move(bytes);
  p.to = to;
  Check(MPI_Isend(p.bytes.data(), static_cast<int>(p.bytes.size()), MPI_BYTE, to, tag,
                  MPI_COMM_WORLD, &p.request),
        "sending to " + Who(to));
}

void Flush(double timeout) {
  if (!Await(timeout, [] { return pending.empty(); }))
    Fail(Who(pending.front().to) + " did not answer within " + Seconds(timeout) +
         " s (taking a message): it died or hangs (ROCKCAL_RANK_TIMEOUT sets the wait)");
}

bool TryReceive(int tag, int* source, std::string* bytes) {
  Progress();
  int flag = 0;
  MPI_Status status;
  Check(MPI_Iprobe(MPI_ANY_SOURCE, tag, MPI_COMM_WORLD, &flag, &status), "waiting for a message");
  if (!flag) return false;
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  bytes->assign(static_cast<std::size_t>(count), '\0');
  Check(MPI_Recv(bytes->data(), count, MPI_BYTE, status.MPI_SOURCE, tag, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE),
        "receiving from " + Who(status.MPI_SOURCE));
  *source = status.MPI_SOURCE;
  return true;
}

std::string Receive(int from, int tag, double timeout, int* source,
                    const std::function<std::string()>& blame) {
  MPI_Status status;
  const bool arrived = Await(timeout, [&] {
    int flag = 0;
    Check(MPI_Iprobe(from < 0 ? MPI_ANY_SOURCE : from, tag, MPI_COMM_WORLD, &flag, &status),
          "waiting for a message");
    return flag != 0;
  });
  if (!arrived)
    Fail(blame() + " did not answer within " + Seconds(timeout) +
         " s: it died or hangs (ROCKCAL_RANK_TIMEOUT sets the wait)");
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::string bytes(static_cast<std::size_t>(count), '\0');
  Check(MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, tag, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE),
        "receiving from " + Who(status.MPI_SOURCE));
  if (source) *source = status.MPI_SOURCE;
  return bytes;
}

std::string Broadcast(const std::string& bytes, double timeout) {
  if (size == 1) return bytes;
  // One message to each rank rather than a collective: a rank that does not
  // take its copy is then known by name.
  if (rank != 0) return Receive(0, kBroadcastTag, timeout, nullptr, [] { return Who(0); });
  for (int r = 1; r < size; ++r) Send(r, kBroadcastTag, bytes);
  Flush(timeout);
  return bytes;
}

void Fail(const std::string& message) {
  const std::string line = "rockcal: failed: " + message + "\n";
  if (::write(terminal, line.data(), line.size()) < 0) {
    // Nowhere left to report it; the exit status still says it failed.
  }
  if (started) MPI_Abort(MPI_COMM_WORLD, 1);
  std::_Exit(1);
}

}  // namespace rockcal::parallel::transport
