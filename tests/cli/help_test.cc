// The command reference (docs/reference/commands.md, built into rockcal for
// --help) against the table the argument reader parses with
// (cli/command_flags.h), both ways, and --help on every command.
#include "help.h"

#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <string>

#include "cli_fixture.h"
#include "command_flags.h"

namespace rockcal::cli {
namespace {

// Every --name the text mentions.
std::set<std::string> FlagsIn(const std::string& text) {
  std::set<std::string> out;
  const std::regex flag("--([a-z][a-z0-9-]*)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), flag); it != std::sregex_iterator();
       ++it)
    out.insert((*it)[1].str());
  return out;
}

std::set<std::string> Accepted(const CommandFlags& c) {
  std::set<std::string> all = c.flags;
  all.insert(c.options.begin(), c.options.end());
  return all;
}

TEST(CommandsReference, IsTheFileInTheSourceTree) {
  EXPECT_EQ(CommandsReference(),
            testing::ReadFile(std::string(ROCKCAL_SOURCE_DIR) + "/docs/reference/commands.md"))
      << "rebuild rockcal: its --help text differs from docs/reference/commands.md";
}

TEST(CommandsReference, NamesEveryFlagTheParserAcceptsAndNoOther) {
  const std::string reference = CommandsReference();
  for (const CommandFlags& c : AllCommandFlags()) {
    const std::string section = CommandHelp(reference, c.command);
    ASSERT_FALSE(section.empty()) << "no section '## rockcal " << c.command
                                  << "' in docs/reference/commands.md";
    const std::set<std::string> documented = FlagsIn(section), accepted = Accepted(c);
    for (const std::string& f : accepted)
      EXPECT_TRUE(documented.count(f))
          << "rockcal " << c.command << " accepts --" << f
          << " but its section of docs/reference/commands.md does not name it";
    for (const std::string& f : documented)
      EXPECT_TRUE(accepted.count(f))
          << "docs/reference/commands.md names --" << f << " under rockcal " << c.command
          << ", which the parser (cli/command_flags.cc) does not accept";
    for (const std::string& m : c.multi)
      EXPECT_TRUE(c.options.count(m)) << c.command << ": repeatable --" << m << " is no option";
  }
}

TEST(CommandsReference, HasASectionForEveryCommandAndNoOther) {
  const std::string reference = CommandsReference();
  const std::regex heading("(^|\n)## rockcal ([^\n]*)");
  int sections = 0;
  for (auto it = std::sregex_iterator(reference.begin(), reference.end(), heading);
       it != std::sregex_iterator(); ++it) {
    ++sections;
    EXPECT_NO_THROW(FlagsOf((*it)[2].str()))
        << "docs/reference/commands.md has a section for '" << (*it)[2].str()
        << "', which is not a command";
  }
  EXPECT_EQ(sections, static_cast<int>(AllCommandFlags().size()));
}

TEST(CommandsReference, OverviewNamesOnlyAcceptedFlags) {
  std::set<std::string> accepted;
  for (const CommandFlags& c : AllCommandFlags()) {
    const std::set<std::string> a = Accepted(c);
    accepted.insert(a.begin(), a.end());
  }
  const std::string overview = OverviewHelp(CommandsReference());
  EXPECT_NE(overview.find("rockcal simulate"), std::string::npos) << overview;
  for (const std::string& f : FlagsIn(overview))
    EXPECT_TRUE(f == "help" || f == "version" || accepted.count(f))
        << "the overview of docs/reference/commands.md names --" << f
        << ", which no command accepts";
}

TEST(CommandHelp, IsTheCommandsSectionAlone) {
  const std::string reference =
      "# title\nintro\n## rockcal a\nA text\n### sub\nmore\n## rockcal b\nB text\n## Other\nX\n";
  EXPECT_EQ(OverviewHelp(reference), "# title\nintro\n");
  EXPECT_EQ(CommandHelp(reference, "a"), "## rockcal a\nA text\n### sub\nmore\n");
  EXPECT_EQ(CommandHelp(reference, "b"), "## rockcal b\nB text\n");
  EXPECT_EQ(CommandHelp(reference, "c"), "");
  EXPECT_EQ(ForTerminal("a\n```\nb\n```\n"), "a\nb\n");
}

// Issue 55: help as a terminal shows it: links as their text, no code or
// bold marks, heading marks or table pipes in prose; code blocks as written.
TEST(ForTerminal, ShowsProseAsPlainText) {
  EXPECT_EQ(ForTerminal("## rockcal a\nexit 2 ([errors.md](errors.md)), `--out DIR`, **draws**\n"
                        "| key | unit |\n|---|:---:|\n| `size` | m |\n```\nrockcal a `x` [y](z)\n```\n"),
            "rockcal a\nexit 2 (errors.md), --out DIR, draws\nkey   unit\nsize   m\n"
            "rockcal a `x` [y](z)\n");
  EXPECT_EQ(ForTerminal("[--draws N | --point-values]] [x](y.md#z)\n"),
            "[--draws N | --point-values]] x\n");
}

TEST(HelpOption, EveryCommandsHelpHasNoMarkdownLinkAndAnExample) {
  const std::string reference = CommandsReference();
  for (const CommandFlags& c : AllCommandFlags()) {
    const std::string help = ForTerminal(CommandHelp(reference, c.command));
    EXPECT_EQ(help.find("]("), std::string::npos) << "rockcal " << c.command << " --help:\n" << help;
    EXPECT_NE(help.find("Example"), std::string::npos) << "rockcal " << c.command << " --help";
  }
  const std::string overview = ForTerminal(OverviewHelp(reference));
  EXPECT_EQ(overview.find("]("), std::string::npos) << overview;
}

TEST(HelpOption, PrintsTheCommandsReferenceAndExitsZeroOnEveryCommand) {
  const std::string reference = CommandsReference();
  for (const CommandFlags& c : AllCommandFlags()) {
    for (const char* help : {"--help", "-h"}) {
      const testing::RunResult r = testing::Rockcal(c.command + " " + help);
      EXPECT_EQ(r.status, 0) << "rockcal " << c.command << " " << help << "\n" << r.err;
      EXPECT_EQ(r.out, ForTerminal(CommandHelp(reference, c.command))) << c.command;
    }
  }
  // Among other arguments, even ones that would be bad input.
  const testing::RunResult study = testing::Rockcal("study reach no-such-site.json --help");
  EXPECT_EQ(study.status, 0) << study.err;
  EXPECT_EQ(study.out, ForTerminal(CommandHelp(reference, "study")));
}

TEST(VersionOption, PrintsTheVersionAndExitsZero) {
  for (const char* args : {"--version", "version"}) {
    const testing::RunResult r = testing::Rockcal(args);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    EXPECT_TRUE(std::regex_match(r.out, std::regex("rockcal [0-9]+\\.[0-9]+\\.[0-9]+\n")))
        << args << " printed '" << r.out << "'";
  }
}

TEST(HelpOption, WithoutACommandPrintsTheOverview) {
  const std::string overview = ForTerminal(OverviewHelp(CommandsReference()));
  for (const char* args : {"--help", "-h", "help"}) {
    const testing::RunResult r = testing::Rockcal(args);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    EXPECT_EQ(r.out, overview) << args;
  }
  const testing::RunResult topic = testing::Rockcal("help calibrate");
  EXPECT_EQ(topic.status, 0);
  EXPECT_EQ(topic.out, ForTerminal(CommandHelp(CommandsReference(), "calibrate")));
  const testing::RunResult bare = testing::Rockcal("");
  EXPECT_EQ(bare.status, 2) << "rockcal without a command is a usage error";
  EXPECT_EQ(bare.err, overview);
  const testing::RunResult unknown = testing::Rockcal("simulat --help");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.err.find("unknown command 'simulat'"), std::string::npos) << unknown.err;
}

}  // namespace
}  // namespace rockcal::cli
