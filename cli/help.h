// rockcal --help and rockcal COMMAND --help print the command reference,
// docs/reference/commands.md, which the build embeds into the program
// (cmake/embed_text.cmake): the usage text is written once.
#ifndef ROCKCAL_CLI_HELP_H_
#define ROCKCAL_CLI_HELP_H_

#include <string>
#include <vector>

namespace rockcal::cli {

// The whole of docs/reference/commands.md as built into rockcal.
std::string CommandsReference();

// What `rockcal --help` prints: the reference's overview, everything before
// the first command's section.
std::string OverviewHelp(const std::string& reference);

// What `rockcal COMMAND --help` prints: the section headed "## rockcal
// COMMAND", up to the next "## " heading; "" when the reference has none.
std::string CommandHelp(const std::string& reference, const std::string& command);

// The section's text as a terminal shows it: Markdown's code fences
// dropped (code lines kept as written) and, in prose, links shown as their
// text ([x](y.md) -> x), no backticks, bold marks, heading marks, table
// pipes or table rules.
std::string ForTerminal(const std::string& markdown);

// Whether the arguments after the command ask for help (--help or -h).
bool AsksForHelp(const std::vector<std::string>& args);

}  // namespace rockcal::cli

#endif  // ROCKCAL_CLI_HELP_H_
