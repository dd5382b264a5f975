// The messages between ranks, the one place that knows MPI
// (transport_mpi.cc); transport_serial.cc is the single process of a build
// without MPI. Internal to rockcal::parallel.
//
// Every wait has a deadline: a rank that does not answer in time is
// reported (Fail) with its rank and host. Fail ends the whole job with exit
// status 1.
#ifndef ROCKCAL_PARALLEL_SRC_TRANSPORT_H_
#define ROCKCAL_PARALLEL_SRC_TRANSPORT_H_

#include <functional>
#include <string>

namespace rockcal::parallel::transport {

bool Available();
// Starts MPI when the process was started by an MPI launcher (mpirun,
// srun): a plain `rockcal` stays a single process without touching MPI.
void Init(int* argc, char*** argv);
void Finalize();
int Rank();
int Size();
std::string Host(int rank);

// Sends `bytes` to rank `to`; returns at once (the send completes while the
// rank waits in a later call, or in Flush).
void Send(int to, int tag, std::string bytes);
// Waits until every Send of this rank has been delivered.
void Flush(double timeout);
// A message with `tag` from any rank, if one has arrived.
bool TryReceive(int tag, int* source, std::string* bytes);
// Waits for a message with `tag` from rank `from` (-1: any), at most
// `timeout` seconds; then Fails, naming `blame()` (what was awaited).
std::string Receive(int from, int tag, double timeout, int* source,
                    const std::function<std::string()>& blame);
// Rank 0's `bytes` on every rank. Rank 0 waits until every rank has taken
// its copy; a rank that does not is named. Tags from 1000 up are the
// transport's own.
std::string Broadcast(const std::string& bytes, double timeout);

// Reports `message` on the terminal (stderr of the launching process, also
// from a rank whose own stderr is silenced) and ends the job with status 1.
[[noreturn]] void Fail(const std::string& message);

}  // namespace rockcal::parallel::transport

#endif  // ROCKCAL_PARALLEL_SRC_TRANSPORT_H_
