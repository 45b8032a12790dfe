#include "export.h"

#include "common.h"
#include "files.h"

#include <bit>
#include <cerrno>
#include <cstring>
#include <fstream>

namespace ink {

void writePointsPly(const std::string& path, const std::vector<PointRecord>& points, const Frame& frame) {
    writeAtomically(path, [&](const std::string& tmp) {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno));
        out << "ply\nformat binary_little_endian 1.0\ncomment inkwell refined points\n"
            << "element vertex " << points.size() << "\n"
            << "property float x\nproperty float y\nproperty float z\n"
            << "property float nx\nproperty float ny\nproperty float nz\n"
            << "property int level\nproperty float rank\nend_header\n";
        std::vector<float> row(8 * points.size());
        for (size_t i = 0; i < points.size(); ++i) {
            const PointRecord& p = points[i];
            Eigen::Vector3d x = frame.toInput(Eigen::Vector3d(p.position[0], p.position[1], p.position[2]));
            float* r = &row[8 * i];
            for (int k = 0; k < 3; ++k) {
                r[k] = float(x[k]);
                r[3 + k] = p.normal[k];
            }
            int32_t level = int32_t(p.level);
            std::memcpy(&r[6], &level, 4);
            r[7] = p.tone;
        }
        static_assert(std::endian::native == std::endian::little, "the PLY writer assumes a little-endian host");
        out.write(reinterpret_cast<const char*>(row.data()), std::streamsize(row.size() * sizeof(float)));
        out.close();
        if (!out) throw Error("cannot write '" + path + "': " + std::strerror(errno));
    });
}

}  // namespace ink
