// The output layer (include/inkwell/files.h, public: the apps write through it too), under the engine's names.
#pragma once

#include "inkwell/files.h"

namespace ink {

using inkwell::checkOutputs;
using inkwell::checkWritable;
using inkwell::OutputBatch;
using inkwell::registeredTemporaries;
using inkwell::registerTemporary;
using inkwell::registerTemporaryDirectory;
using inkwell::removeTemporariesOnSignals;
using inkwell::sameFile;
using inkwell::unregisterTemporary;
using inkwell::writeAll;
using inkwell::writeAtomically;
using inkwell::writeFileAtomically;

}  // namespace ink
