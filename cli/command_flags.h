// What each rockcal command accepts on its command line: the one table the
// argument reader (args.h) parses with, and that tests/cli/help_test.cc checks
// against the command reference (docs/reference/commands.md) both ways.
#ifndef ROCKCAL_CLI_COMMAND_FLAGS_H_
#define ROCKCAL_CLI_COMMAND_FLAGS_H_

#include <set>
#include <string>
#include <vector>

namespace rockcal::cli {

struct CommandFlags {
  std::string command;            // "simulate", "study", ...
  std::set<std::string> flags;    // --name, no value
  std::set<std::string> options;  // --name VALUE (or --name=VALUE)
  std::set<std::string> multi;    // the options that may repeat
};

// Every command, in the reference's order.
const std::vector<CommandFlags>& AllCommandFlags();

// The entry of `command`; a programmer error (std::logic_error) when there is none.
const CommandFlags& FlagsOf(const std::string& command);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_COMMAND_FLAGS_H_
