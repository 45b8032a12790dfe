// tinyobjloader's implementation compiled into the fuzz build, so that the sanitizers and libFuzzer's
// coverage see inside it too (the normal build links Debian's libtinyobjloader, built from this header).
#if defined(__clang__)
#pragma clang diagnostic ignored "-Wunused-parameter"
#pragma clang diagnostic ignored "-Wsign-compare"
#pragma clang diagnostic ignored "-Wunused-but-set-variable"
#endif
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
