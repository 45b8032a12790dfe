#include "draw/page_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ink {

namespace {

// The points in cells of side `cell`, for nearest-neighbour searches ring by ring.
struct PointGrid {
    double cell;
    int nx, ny;
    std::vector<uint32_t> start, items;
    const std::vector<double>& x;
    const std::vector<double>& y;

    PointGrid(const std::vector<double>& px, const std::vector<double>& py, double width, double height, double side)
        : cell(side), x(px), y(py) {
        nx = std::max(1, int(std::ceil(width / cell)));
        ny = std::max(1, int(std::ceil(height / cell)));
        start.assign(size_t(nx) * size_t(ny) + 1, 0);
        for (size_t i = 0; i < x.size(); ++i) ++start[index(x[i], y[i]) + 1];
        for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
        items.resize(x.size());
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (size_t i = 0; i < x.size(); ++i) items[fill[index(x[i], y[i])]++] = uint32_t(i);
    }
    int clampX(double v) const { return std::clamp(int(std::floor(v / cell)), 0, nx - 1); }
    int clampY(double v) const { return std::clamp(int(std::floor(v / cell)), 0, ny - 1); }
    size_t index(double px, double py) const { return size_t(clampY(py)) * size_t(nx) + size_t(clampX(px)); }

    // The distance from point i to its nearest other point (infinity when it is alone).
    double nearest(size_t i) const {
        const int cx = clampX(x[i]), cy = clampY(y[i]);
        double best = std::numeric_limits<double>::infinity();
        for (int ring = 0; ring <= std::max(nx, ny); ++ring) {
            // Every point outside the rings searched so far is at least (ring − 1) cells away.
            if (ring > 1 && double(ring - 1) * cell > best) break;
            for (int gy = cy - ring; gy <= cy + ring; ++gy) {
                if (gy < 0 || gy >= ny) continue;
                const bool edgeRow = gy == cy - ring || gy == cy + ring;
                for (int gx = cx - ring; gx <= cx + ring; gx += edgeRow ? 1 : 2 * std::max(ring, 1)) {
                    if (gx < 0 || gx >= nx) continue;
                    const size_t c = size_t(gy) * size_t(nx) + size_t(gx);
                    for (uint32_t k = start[c]; k < start[c + 1]; ++k)
                        if (items[k] != i) best = std::min(best, std::hypot(x[items[k]] - x[i], y[items[k]] - y[i]));
                }
            }
        }
        return best;
    }
};

}  // namespace

PageMetrics measurePage(const std::vector<gpu::Dot>& dots, uint32_t width, uint32_t height, double window,
                        double dotDiameter, double margin, size_t minDots) {
    PageMetrics m;
    std::vector<double> fx, fy, fInk, ox, oy;
    for (const gpu::Dot& d : dots) {
        const uint32_t shown = (d.cls >> 2) & 3u;
        if (shown == gpu::FRONT && (d.state == gpu::SPACE_ACCEPTED || d.state == gpu::SPACE_FIXED)) {
            fx.push_back(d.pixel.x);
            fy.push_back(d.pixel.y);
            const double diameter = dotDiameter * double(d.scale);
            fInk.push_back(0.25 * M_PI * diameter * diameter);
            m.largerDots += d.scale > 1.0f;
        } else if (shown == gpu::SILHOUETTE || shown == gpu::HIDDEN) {
            ox.push_back(d.pixel.x);
            oy.push_back(d.pixel.y);
        }
    }
    m.frontDots = fx.size();
    m.outlineDots = ox.size();
    if (fx.empty() || !(window > 0)) return m;
    const PointGrid front(fx, fy, width, height, std::max(1.0, window / 8));
    std::vector<double> nearest(fx.size());
    for (size_t i = 0; i < fx.size(); ++i) nearest[i] = front.nearest(i);
    // Outline dots by grid cell of the windows' step, to skip windows near the outline.
    const double step = window / 4;
    const int sx = std::max(1, int(std::ceil(double(width) / step))),
              sy = std::max(1, int(std::ceil(double(height) / step)));
    std::vector<uint8_t> outlineCell(size_t(sx) * size_t(sy), 0);
    auto markOutline = [&](double x0, double y0, double x1, double y1) {
        for (int gy = std::max(0, int(std::floor(y0 / step))); gy <= std::min(sy - 1, int(std::floor(y1 / step))); ++gy)
            for (int gx = std::max(0, int(std::floor(x0 / step))); gx <= std::min(sx - 1, int(std::floor(x1 / step)));
                 ++gx)
                outlineCell[size_t(gy) * size_t(sx) + size_t(gx)] = 1;
    };
    for (size_t i = 0; i < ox.size(); ++i) markOutline(ox[i] - margin, oy[i] - margin, ox[i] + margin, oy[i] + margin);
    const PointGrid byStep(fx, fy, width, height, step);
    m.worstNearest = m.leastCoverage = std::numeric_limits<double>::infinity();
    const int span = int(std::lround(window / step));  // steps a window
    for (int wy = 0; double(wy) * step + window <= double(height); ++wy)
        for (int wx = 0; double(wx) * step + window <= double(width); ++wx) {
            bool nearOutline = false;
            for (int gy = wy; gy < wy + span && gy < sy && !nearOutline; ++gy)
                for (int gx = wx; gx < wx + span && gx < sx && !nearOutline; ++gx)
                    nearOutline = outlineCell[size_t(gy) * size_t(sx) + size_t(gx)] != 0;
            if (nearOutline) continue;
            PageWindow w;
            w.x0 = double(wx) * step;
            w.y0 = double(wy) * step;
            std::vector<uint32_t> inside;
            for (int gy = wy; gy < wy + span && gy < byStep.ny; ++gy)
                for (int gx = wx; gx < wx + span && gx < byStep.nx; ++gx) {
                    const size_t c = size_t(gy) * size_t(byStep.nx) + size_t(gx);
                    for (uint32_t k = byStep.start[c]; k < byStep.start[c + 1]; ++k) {
                        const uint32_t i = byStep.items[k];
                        if (fx[i] >= w.x0 && fx[i] < w.x0 + window && fy[i] >= w.y0 && fy[i] < w.y0 + window)
                            inside.push_back(i);
                    }
                }
            if (inside.size() < std::max<size_t>(minDots, 2)) continue;
            w.dots = inside.size();
            const double rMax = std::sqrt(2.0 * window * window / (std::sqrt(3.0) * double(w.dots)));
            double ink = 0;
            for (uint32_t i : inside) {
                w.meanNearest += nearest[i] / rMax / double(w.dots);
                w.clumped += (nearest[i] < 0.5 * rMax) / double(w.dots);
                ink += fInk[i];
            }
            w.coverage = ink / (window * window);
            m.windows.push_back(w);
            m.meanNearest += w.meanNearest;
            m.worstNearest = std::min(m.worstNearest, w.meanNearest);
            m.worstClumped = std::max(m.worstClumped, w.clumped);
            m.leastCoverage = std::min(m.leastCoverage, w.coverage);
            m.mostCoverage = std::max(m.mostCoverage, w.coverage);
        }
    if (m.windows.empty()) {
        m.worstNearest = m.leastCoverage = 0;
    } else {
        m.meanNearest /= double(m.windows.size());
    }
    return m;
}

}  // namespace ink
