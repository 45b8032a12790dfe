// The CPU twin of spacing.comp (screen_spacing.h): the same grid, elections and float comparisons. Built with
// -ffp-contract=off (CMakeLists.txt), as the shader marks its distances `precise`.
#include "draw/screen_spacing.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <bit>
#include <cmath>

namespace ink {

namespace {

constexpr uint32_t kNone = 0xFFFFFFFFu;

bool conflict(const gpu::Dot& a, const gpu::Dot& b) {
    float dx = a.pixel.x - b.pixel.x;
    float dy = a.pixel.y - b.pixel.y;
    float d2 = dx * dx + dy * dy;
    float r = std::min(a.radius, b.radius);
    return d2 < r * r;
}

bool before(uint32_t keyA, uint32_t pointA, uint32_t keyB, uint32_t pointB) {
    return keyA < keyB || (keyA == keyB && pointA < pointB);
}

// spacing.comp's displacement() and atMost().
glm::vec2 displacement(uint32_t word, float radius) {
    return glm::unpackSnorm2x16(word) * (gpu::SPACE_RELAX_MAX * radius);
}

glm::vec2 atMost(glm::vec2 v, float most) {
    float l2 = v.x * v.x + v.y * v.y;
    if (l2 <= most * most) return v;
    return v * (most / std::sqrt(l2));
}

}  // namespace

void spaceDotsOnCpu(std::vector<gpu::Dot>& dots, uint32_t width, uint32_t height, float inverseCell) {
    const int sx = int(std::ceil(float(width) * inverseCell)), sy = int(std::ceil(float(height) * inverseCell));
    const size_t cells = size_t(sx) * size_t(sy);
    std::vector<uint32_t> key(cells), point(cells), elected(cells), accepted(cells, kNone);
    auto cellOf = [&](const gpu::Dot& d, int& cx, int& cy) {
        float x = d.pixel.x * inverseCell, y = d.pixel.y * inverseCell;
        cx = std::clamp(int(std::floor(x)), 0, sx - 1);
        cy = std::clamp(int(std::floor(y)), 0, sy - 1);
        return size_t(cy) * size_t(sx) + size_t(cx);
    };
    // Calls visit(n) for every cell n within the dot's reach.
    auto around = [&](const gpu::Dot& d, int cx, int cy, auto&& visit) {
        int reach = int(std::ceil(d.radius * inverseCell));
        for (int y = std::max(cy - reach, 0); y <= std::min(cy + reach, sy - 1); ++y)
            for (int x = std::max(cx - reach, 0); x <= std::min(cx + reach, sx - 1); ++x)
                visit(size_t(y) * size_t(sx) + size_t(x));
    };
    for (uint32_t round = 0; round < gpu::SPACE_ROUNDS; ++round) {
        std::fill(key.begin(), key.end(), kNone);
        std::fill(point.begin(), point.end(), kNone);
        std::fill(elected.begin(), elected.end(), kNone);
        // PASS_CLAIM_KEY: rejected by an earlier round's accepted dot, else the cell's lowest key. Every decision
        // reads the grid as the round began, like the shader's barriers make it.
        for (gpu::Dot& d : dots) {
            if (d.state != gpu::SPACE_OPEN) continue;
            int cx, cy;
            size_t cell = cellOf(d, cx, cy);
            bool covered = false;
            around(d, cx, cy, [&](size_t n) { covered |= accepted[n] != kNone && conflict(d, dots[accepted[n]]); });
            if (covered)
                d.state = gpu::SPACE_REJECTED;
            else
                key[cell] = std::min(key[cell], d.key);
        }
        for (const gpu::Dot& d : dots) {  // PASS_CLAIM_POINT
            int cx, cy;
            size_t cell = cellOf(d, cx, cy);
            if (d.state == gpu::SPACE_OPEN && key[cell] == d.key) point[cell] = std::min(point[cell], d.cls >> 4);
        }
        for (uint32_t i = 0; i < dots.size(); ++i) {  // PASS_CLAIM_DOT
            int cx, cy;
            size_t cell = cellOf(dots[i], cx, cy);
            if (dots[i].state == gpu::SPACE_OPEN && key[cell] == dots[i].key && point[cell] == dots[i].cls >> 4)
                elected[cell] = i;
        }
        std::vector<uint32_t> accept;  // PASS_DECIDE
        for (uint32_t i = 0; i < dots.size(); ++i) {
            const gpu::Dot& d = dots[i];
            int cx, cy;
            size_t cell = cellOf(d, cx, cy);
            if (d.state != gpu::SPACE_OPEN || elected[cell] != i) continue;
            bool blocked = false;
            around(d, cx, cy, [&](size_t n) {
                if (n == cell || key[n] == kNone) return;
                blocked |= before(key[n], point[n], d.key, d.cls >> 4) && conflict(d, dots[elected[n]]);
            });
            if (!blocked) accept.push_back(i);
        }
        for (uint32_t i : accept) {
            int cx, cy;
            dots[i].state = gpu::SPACE_ACCEPTED;
            accepted[cellOf(dots[i], cx, cy)] = i;
        }
    }
    // PASS_RELAX: each step reads the displacements of the last (plane `from`) and writes the next; PASS_PLACE.
    if (cells < gpu::SPACE_RELAX_MIN_CELLS) return;
    // The blocks' masks of the cells that hold an accepted dot (PASS_LIST), visited as the shader does.
    const int blocksX = (sx + int(gpu::SPACE_BLOCK) - 1) / int(gpu::SPACE_BLOCK);
    const int blocksY = (sy + int(gpu::SPACE_BLOCK) - 1) / int(gpu::SPACE_BLOCK);
    std::vector<uint32_t> masks(size_t(blocksX) * size_t(blocksY), 0);
    for (size_t n = 0; n < cells; ++n)
        if (accepted[n] != kNone) {
            const uint32_t x = uint32_t(n % size_t(sx)), y = uint32_t(n / size_t(sx));
            masks[y / gpu::SPACE_BLOCK * uint32_t(blocksX) + x / gpu::SPACE_BLOCK] |=
                1u << (y % gpu::SPACE_BLOCK * gpu::SPACE_BLOCK + x % gpu::SPACE_BLOCK);
        }
    std::vector<uint32_t> from(cells, 0), to(cells, 0);
    for (uint32_t step = 0; step < gpu::SPACE_RELAX_ROUNDS; ++step) {
        for (const gpu::Dot& d : dots) {
            if (d.state != gpu::SPACE_ACCEPTED) continue;
            int cx, cy;
            const size_t cell = cellOf(d, cx, cy);
            glm::vec2 moved = displacement(from[cell], d.radius);
            const glm::vec2 p = d.pixel + moved;
            const float reach = gpu::SPACE_RELAX_REACH * d.radius, reach2 = reach * reach;
            const int search = int(std::ceil(reach * inverseCell));
            glm::vec2 push(0.0f), around(0.0f);
            uint32_t neighbours = 0;
            float room = 2.0f * gpu::SPACE_RELAX_STEP_MAX * d.radius;
            const int block = int(gpu::SPACE_BLOCK);
            for (int by = std::max(cy - search, 0) / block; by <= std::min(cy + search, sy - 1) / block; ++by)
                for (int bx = std::max(cx - search, 0) / block; bx <= std::min(cx + search, sx - 1) / block; ++bx)
                    for (uint32_t mask = masks[size_t(by) * size_t(blocksX) + size_t(bx)]; mask != 0;
                         mask &= mask - 1) {
                        const int bit = std::countr_zero(mask);
                        const size_t n =
                            size_t(by * block + bit / block) * size_t(sx) + size_t(bx * block + bit % block);
                        if (n == cell) continue;
                        const gpu::Dot& e = dots[accepted[n]];
                        const glm::vec2 q = e.pixel + displacement(from[n], e.radius);
                        const glm::vec2 delta = p - q;
                        const float d2 = delta.x * delta.x + delta.y * delta.y;
                        if (d2 >= reach2) continue;
                        push += delta * (reach2 - d2);
                        around += delta;
                        ++neighbours;
                        room = std::min(room, std::sqrt(d2) - gpu::SPACE_RELAX_FLOOR * std::min(d.radius, e.radius));
                    }
            const float edge = gpu::SPACE_RELAX_EDGE * reach * float(neighbours);
            if (neighbours >= 3 && around.x * around.x + around.y * around.y <= edge * edge) {
                const glm::vec2 pushed = push * (gpu::SPACE_RELAX_STEP / reach2);
                const glm::vec2 next =
                    moved + atMost(pushed, std::min(gpu::SPACE_RELAX_STEP_MAX * d.radius, 0.5f * std::max(room, 0.0f)));
                const float most = gpu::SPACE_RELAX_MAX * d.radius;
                if (next.x * next.x + next.y * next.y <= most * most) moved = next;
            }
            to[cell] = glm::packSnorm2x16(moved / (gpu::SPACE_RELAX_MAX * d.radius));
        }
        std::swap(from, to);
    }
    for (gpu::Dot& d : dots) {
        if (d.state != gpu::SPACE_ACCEPTED) continue;
        int cx, cy;
        d.pixel += displacement(from[cellOf(d, cx, cy)], d.radius);
    }
}

}  // namespace ink
