// The distributed engine: a run spread over the processes (ranks) of an MPI
// job, or a single process when rockcal is built without MPI or started
// without mpirun. The rest of rockcal calls these functions and never MPI.
//
// Replicated control. Every rank runs the same deterministic driver (the
// command, the optimiser, the study) on the same inputs; only the expensive
// calls are shared out:
//  - Simulate: the rocks of one simulation in contiguous blocks over the
//    ranks (OpenMP inside each), the records gathered so that every rank
//    holds the whole result, bit for bit the single-process one;
//  - Map: a known list of independent tasks (design points, sensitivity
//    rows) handed out one by one to whichever rank is free, every rank
//    receiving every result in task order.
// So every rank takes the same decisions, and only rank 0 writes files and
// prints (the other ranks' stdout and stderr go to /dev/null; rockcal's own
// reports of a failed rank still reach the terminal).
//
// A rank that dies or does not answer within the deadline (RankTimeout) is
// reported with its rank and host, and the job ends with exit status 1 (the
// calibration's evaluation log, appended and flushed by rank 0 after every
// evaluation, stays whole for --resume, on any rank count).
#ifndef ROCKCAL_PARALLEL_PARALLEL_H_
#define ROCKCAL_PARALLEL_PARALLEL_H_

#include <functional>
#include <string>
#include <vector>

#include "rockcal/core/simulate.h"

namespace rockcal::parallel {

// One per process, first thing in main (MPI_Init, MPI_Finalize). Without MPI
// or outside mpirun: a single rank.
class Session final {
 public:
  Session(int* argc, char*** argv);
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

// Whether this build has MPI.
bool Available();
int Rank();       // 0 ... Size() - 1
int Size();       // ranks in the job, 1 without MPI
bool IsRoot();    // Rank() == 0: the rank that writes files and prints
std::string Host(int rank);  // the host a rank runs on

// Seconds a rank waits for another before it reports that rank as dead or
// hung: ROCKCAL_RANK_TIMEOUT (seconds) when set, else the larger of 600 s
// and 20 times the longest simulation or task this rank ran itself.
double RankTimeout();

// All rocks of `scene` spread over the ranks: rank r simulates the r-th of
// Size() contiguous blocks, and every rank returns the joined result,
// identical to core::Simulate's. `progress` counts the rocks of this rank's
// block, scaled to the whole run. Within a Map task, the whole simulation
// runs on the task's rank.
core::SimulationResult Simulate(const core::Scene& scene, const core::Terrain& terrain,
                                const core::ProgressFn& progress = nullptr);
// Same, building the terrain.
core::SimulationResult Simulate(const core::Scene& scene);

// Runs task(0) ... task(count - 1), each on one rank, and returns their
// results (bytes, see Writer / Reader) in task order on every rank. Rank 0
// hands the tasks out as ranks become free and runs tasks itself meanwhile.
// `done(index, result)`, on rank 0 only, follows each task as it finishes
// (in finishing order). A task that throws makes Map throw the same error on
// every rank (the first failing task's). Nested calls run locally.
std::vector<std::string> Map(int count, const std::function<std::string(int)>& task,
                             const std::function<void(int, const std::string&)>& done = nullptr);

// Rank 0's `value` on every rank: for decisions every rank must take alike
// but that depend on the clock (a time budget).
bool RootDecides(bool value);

// Runs `work` on rank 0 only (preparing or writing the output folder) and
// throws its error, if any, on every rank: an InputError as an InputError
// (exit 2), anything else as std::runtime_error.
void OnRoot(const std::function<void()>& work);

// The files of rank 0's `folder` whose names `wanted` accepts (as rank 0
// sees them), copied on every other rank into `into`; rank 0 copies
// nothing. For the evaluation logs a resumed calibration replays on every
// rank.
void ShareFiles(const std::string& folder, const std::function<bool(const std::string&)>& wanted,
                const std::string& into);

// A folder of this rank's own, removed when the Session ends (the output
// folder of a rank other than 0: what it writes there is thrown away).
std::string ScratchFolder();

// Bytes of plain values for Map's results.
class Writer final {
 public:
  void Int(long long v);
  void Double(double v);
  void Doubles(const std::vector<double>& v);
  void String(const std::string& v);
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

class Reader final {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  long long Int();
  double Double();
  std::vector<double> Doubles();
  std::string String();
  bool done() const { return at_ == bytes_.size(); }

 private:
  void Take(void* to, std::size_t n);
  const std::string& bytes_;
  std::size_t at_ = 0;
};

// A simulation's records as bytes and back (every field, doubles bit for
// bit): what the ranks exchange.
std::string EncodeResult(const core::SimulationResult& result);
core::SimulationResult DecodeResult(const std::string& bytes);

}  // namespace rockcal::parallel

#endif  // ROCKCAL_PARALLEL_PARALLEL_H_
