// The evaluation log that `rockcal calibrate --resume` reads
// (calibrate::EvaluationLog): any log is read or refused with an InputError,
// never a crash, undefined behaviour or another exception. A log that was
// read is rewritten, and the rewritten log must read back to the same
// records. An input "\xff" D1 D2 REST nests REST deeply (fuzz_input.h).
#include "fuzz_input.h"
#include "rockcal/calibrate/calibration.h"
#include "rockcal/core/error.h"

namespace {

namespace calibrate = rockcal::calibrate;

// Two parameters of one material, seed 1, 6 rocks; the fingerprint of the
// seed corpus (fuzz/seeds/evaluation_log_fuzz/).
const calibrate::ParameterSpace& Space() {
  static const calibrate::ParameterSpace space = [] {
    calibrate::Parameter hardness, roughness;
    hardness.material = roughness.material = "slope";
    hardness.kind = calibrate::ParameterKind::kHardness;
    roughness.kind = calibrate::ParameterKind::kRoughness;
    roughness.lower = 0.01;
    roughness.upper = 0.5;
    return calibrate::ParameterSpace({hardness, roughness});
  }();
  return space;
}

calibrate::Fingerprint Expected() {
  calibrate::Fingerprint f;
  f.Add("site file", "0123456789abcdef");
  f.Add("seed", "1");
  return f;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path =
      rockcal::fuzz::WriteText(rockcal::fuzz::Nested(data, size), "_evaluations.jsonl");
  int records = -1;
  try {
    const calibrate::EvaluationLog log(path, true, Space(), 1, 6, Expected());
    records = log.size();
  } catch (const rockcal::InputError&) {
    return 0;
  }
  // The log as rewritten: the same records, each found again.
  const calibrate::EvaluationLog again(path, true, Space(), 1, 6, Expected());
  if (again.size() != records) __builtin_trap();
  return 0;
}
