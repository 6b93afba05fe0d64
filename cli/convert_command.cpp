// `scancrew convert IN.sclog OUT.mcap`: an old recording (.sclog, retired) written again as
// MCAP, the format the recorder now writes and the replay backend reads (docs/recording.md).

#include <cstdio>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "components/recorder/log_file.hpp"
#include "executors/log.hpp"

namespace scancrew::cli {

namespace {

struct ConvertOptions {
  std::string in, out;
};

int convert(const ConvertOptions& o) {
  const auto done = recorder::convert_sclog(o.in, o.out);
  if (!done) {
    std::fprintf(stderr, "scancrew convert: %s\n", log::printable(done.error()).c_str());
    return 1;
  }
  std::printf("convert: %s: %llu topics, %llu messages%s\n", o.out.c_str(),
              static_cast<unsigned long long>(done->topics),
              static_cast<unsigned long long>(done->messages),
              done->truncated ? " (the .sclog is cut short: converted up to the cut)" : "");
  return 0;
}

}  // namespace

void add_convert_command(CLI::App& app, CommandTable& table) {
  auto [command, o] = table.add_with_options<ConvertOptions>(
      app, "convert",
      "write an old .sclog recording as MCAP (.mcap), the format the recorder writes and replay "
      "reads; topics, types, receive times and message bytes are kept (docs/recording.md)",
      convert);
  command->add_option("in", o->in, "the .sclog recording to read")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("out", o->out, "the .mcap recording to write (overwritten)")->required();
}

}  // namespace scancrew::cli
