// A build without MPI: one process, nothing to send.
#include <cstdio>
#include <cstdlib>

#include "transport.h"

namespace rockcal::parallel::transport {

bool Available() { return false; }
void Init(int*, char***) {}
void Finalize() {}
int Rank() { return 0; }
int Size() { return 1; }
std::string Host(int) { return "localhost"; }

void Send(int, int, std::string) { Fail("no other rank to send to (built without MPI)"); }
void Flush(double) {}
bool TryReceive(int, int*, std::string*) { return false; }
std::string Receive(int, int, double, int*, const std::function<std::string()>&) {
  Fail("no other rank to receive from (built without MPI)");
}
std::string Broadcast(const std::string& bytes, double) { return bytes; }

void Fail(const std::string& message) {
  std::fprintf(stderr, "rockcal: failed: %s\n", message.c_str());
  std::exit(1);
}

}  // namespace rockcal::parallel::transport
