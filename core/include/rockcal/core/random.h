// Deterministic random streams: one per rock, keyed by (seed, stream); the
// simulation keys a rock's stream by its group and its index within the group.
#ifndef ROCKCAL_CORE_RANDOM_H_
#define ROCKCAL_CORE_RANDOM_H_

#include <cstdint>

namespace rockcal::core {

// xoshiro256** seeded through splitmix64 from (seed, stream).
class RandomStream final {
 public:
  RandomStream(std::uint64_t seed, std::uint64_t stream);
  std::uint64_t NextU64();
  double Uniform();                      // [0, 1)
  double Uniform(double lo, double hi);  // [lo, hi)
  std::size_t Index(std::size_t n);      // a whole number in [0, n), n >= 1, from Uniform()
  double Normal();                       // standard normal (Box-Muller)

 private:
  std::uint64_t s_[4];
};

}  // namespace rockcal::core

#endif  // ROCKCAL_CORE_RANDOM_H_
