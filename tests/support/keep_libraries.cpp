// Linked into the executables of the sanitizer build only (INKWELL_SANITIZE; docs/robustness.md).
//
// The Vulkan loader dlclose()s the drivers and layers (lavapipe, the validation layer) when the instance is
// destroyed, before LeakSanitizer looks for leaks at exit. Their small one-time leaks are then reported from
// "<unknown module>", which no suppression can match. This dlclose() takes precedence over libc's for every
// library in the process and keeps the library loaded, so that leaks inside it are named by their library
// and tests/support/lsan.supp can suppress them by name. Nothing else changes: a library is never opened twice.
extern "C" int dlclose(void*) { return 0; }
