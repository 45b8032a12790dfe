#include "commands.h"

namespace app {

void addValidateCommand(CLI::App&, Options&, Commands&) {}

}  // namespace app
