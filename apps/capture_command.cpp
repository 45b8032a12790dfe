#include "commands.h"

namespace app {

void addCaptureCommands(CLI::App&, Options&, Commands&) {}

}  // namespace app
