// The CPU–GPU interface's prelude: what lets the other headers of spirv_shaders/shared/ be read by both GLSL
// (#include, GL_GOOGLE_include_directive) and C++ (engine/). They are written in the subset the two languages
// share: `INK_CONST uint NAME = 1u;` constants, plain structs of GLSL types, `//` comments. In C++ the GLSL
// types are glm's (vec4 is glm::vec4, uint is uint32_t) in namespace ink::gpu, and every struct that crosses is
// checked with static_assert on its size and offsets (INK_ASSERT_LAYOUT, compiled only as C++). The rule
// (docs/contributing.md): whatever crosses the boundary (a binding, a workgroup size, a limit, a flag bit, a
// struct's layout) is written here once and nowhere else.
#ifndef INK_SHARED_INTERFACE_H
#define INK_SHARED_INTERFACE_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>

#define INK_CONST inline constexpr
#define INK_BEGIN namespace ink::gpu {
#define INK_END }
// static_assert(offsetof(...)) in C++, nothing in GLSL.
#define INK_ASSERT_SIZE(T, bytes) static_assert(sizeof(T) == (bytes), #T "'s size differs from the GLSL layout")
#define INK_ASSERT_OFFSET(T, member, bytes) \
    static_assert(offsetof(T, member) == (bytes), #T "::" #member "'s offset differs from the GLSL layout")

namespace ink::gpu {
using uint = uint32_t;
using vec2 = glm::vec2;
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using uvec4 = glm::uvec4;
using dvec4 = glm::dvec4;
using mat4 = glm::mat4;
}  // namespace ink::gpu
#else
#define INK_CONST const
#define INK_BEGIN
#define INK_END
#define INK_ASSERT_SIZE(T, bytes)
#define INK_ASSERT_OFFSET(T, member, bytes)
#endif

#endif
