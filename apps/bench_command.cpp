#include "commands.h"

namespace app {

void addBenchCommand(CLI::App&, Options&, Commands&) {}

}  // namespace app
