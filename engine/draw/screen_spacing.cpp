// The CPU twin of spacing.comp (screen_spacing.h): the same grid, elections and float comparisons. Built with
// -ffp-contract=off (CMakeLists.txt), as the shader marks its distances `precise`.
#include "draw/screen_spacing.h"

#include <algorithm>
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
}

}  // namespace ink
