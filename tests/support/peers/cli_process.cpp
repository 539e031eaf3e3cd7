#include "tests/support/peers/cli_process.hpp"

#include "tests/support/temp_files.hpp"

namespace unima::test_support {

namespace {
std::vector<std::string> with_program(std::vector<std::string> args) {
  args.insert(args.begin(), UNIMA_BRIDGE_CLI);
  return args;
}
}  // namespace

CliProcess::CliProcess(const std::filesystem::path& output, std::vector<std::string> args)
    : output_(output), process_(with_program(std::move(args)), stopped_by_sigterm(output)) {}

std::string CliProcess::output() const { return read_file(output_); }

}  // namespace unima::test_support
