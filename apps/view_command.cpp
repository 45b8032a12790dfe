#include "commands.h"

namespace app {

void addViewCommand(CLI::App&, Options&, Commands&) {}

}  // namespace app
