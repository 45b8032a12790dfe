#include "io/hrbf_io.h"

#include "base/common.h"
#include "base/files.h"
#include "base/parallel.h"
#include "surface/surface.h"

#include <Eigen/Geometry>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <utility>
#include <vector>

#if defined(__x86_64__)
#include <nmmintrin.h>
#endif

namespace ink {
namespace {

// ---- CRC-32C: slicing by 8 tables, or the SSE 4.2 instruction where the CPU has it

struct Crc32cTables {
    uint32_t t[8][256];
    Crc32cTables() {
        for (uint32_t i = 0; i < 256; ++i) {
            uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? (c >> 1) ^ 0x82F63B78u : c >> 1;
            t[0][i] = c;
        }
        for (uint32_t i = 0; i < 256; ++i)
            for (int k = 1; k < 8; ++k) t[k][i] = (t[k - 1][i] >> 8) ^ t[0][t[k - 1][i] & 0xff];
    }
};

uint32_t crcTables(const unsigned char* p, size_t n, uint32_t crc) {
    static const Crc32cTables tables;
    const auto& t = tables.t;
    for (; n >= 8; p += 8, n -= 8) {
        uint64_t w;
        std::memcpy(&w, p, 8);
        w ^= crc;
        crc = t[7][w & 0xff] ^ t[6][(w >> 8) & 0xff] ^ t[5][(w >> 16) & 0xff] ^ t[4][(w >> 24) & 0xff] ^
              t[3][(w >> 32) & 0xff] ^ t[2][(w >> 40) & 0xff] ^ t[1][(w >> 48) & 0xff] ^ t[0][w >> 56];
    }
    for (; n > 0; ++p, --n) crc = t[0][(crc ^ *p) & 0xff] ^ (crc >> 8);
    return crc;
}

#if defined(__x86_64__)
__attribute__((target("sse4.2"))) uint32_t crcSse42(const unsigned char* p, size_t n, uint32_t crc) {
    uint64_t c = crc;
    for (; n >= 8; p += 8, n -= 8) {
        uint64_t w;
        std::memcpy(&w, p, 8);
        c = _mm_crc32_u64(c, w);
    }
    for (; n > 0; ++p, --n) c = _mm_crc32_u8(uint32_t(c), *p);
    return uint32_t(c);
}
#endif

}  // namespace

uint32_t crc32c(std::string_view bytes, uint32_t crc) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data());
#if defined(__x86_64__)
    static const bool sse42 = __builtin_cpu_supports("sse4.2");
    if (sse42) return ~crcSse42(p, bytes.size(), ~crc);
#endif
    return ~crcTables(p, bytes.size(), ~crc);
}

namespace {

constexpr const char* kMagic = "inkwell-hrbf";
constexpr int kVersion = 2;           // 1: the global fit; 2: the partition of unity. Both are read and written.
constexpr size_t kCenterFields = 10;  // x y z nx ny nz alpha bx by bz
// The shortest centre line: ten one-digit numbers, nine separators and a newline. Bounds the count a file
// of a given size can hold, so that a hostile count is refused before anything is allocated for it.
constexpr size_t kMinCenterLineBytes = 2 * kCenterFields;
// How far a loaded model may miss its own centres and normals (a fit misses by about 1e-6 at most): the
// distance |f|/|grad f| as a fraction of the diagonal, the angle between grad f and n, and |grad f - n|/|n|.
constexpr double kMaxLoadedDistance = 1e-3;
constexpr double kMaxLoadedAngleDeg = 1.0;
constexpr double kMaxLoadedGradientMismatch = 1e-2;

[[noreturn]] void fail(const std::string& name, const std::string& what) { throw Error(name + ": " + what); }

// The meaningful lines of the file split into whitespace-separated fields; blank lines and lines starting
// with '#' are skipped. Lines end in "\n" or "\r\n". Only the first few fields are kept (a line has at
// most ten), so that a huge line of garbage costs no memory; `count` has them all.
class Lines {
public:
    Lines(std::string_view bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}

    bool next() {
        while (pos_ < bytes_.size()) {
            size_t end = bytes_.find('\n', pos_);
            if (end == std::string_view::npos) end = bytes_.size();
            std::string_view line = bytes_.substr(pos_, end - pos_);
            pos_ = end + 1;
            ++number_;
            fields.clear();
            count = 0;
            size_t i = 0;
            while (i < line.size()) {
                while (i < line.size() && isSpace(line[i])) ++i;
                size_t start = i;
                while (i < line.size() && !isSpace(line[i])) ++i;
                if (i == start) continue;
                if (++count <= kMaxFields) fields.push_back(line.substr(start, i - start));
            }
            if (count > 0 && fields[0][0] != '#') return true;
        }
        fields.clear();
        count = 0;
        return false;
    }

    [[noreturn]] void fail(const std::string& what) const {
        ink::fail(name_, "line " + std::to_string(number_) + ": " + what);
    }
    size_t line() const { return number_; }

    double real(size_t field) const {
        std::string_view s = fields[field];
        if (!s.empty() && s[0] == '+') s.remove_prefix(1);  // from_chars takes no '+'; people write one
        double v = 0;
        auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (ec == std::errc::result_out_of_range) fail(quoted(fields[field]) + " is out of range for a double");
        if (ec != std::errc() || end != s.data() + s.size()) fail(quoted(fields[field]) + " is not a number");
        if (!std::isfinite(v)) fail(quoted(fields[field]) + " is not finite");
        return v;
    }

    Eigen::Vector3d vector(size_t first) const { return {real(first), real(first + 1), real(first + 2)}; }

    // A `key n1 n2 ...` line with `count` numbers; `usage` spells it for the message.
    void expectKey(const char* key, size_t numbers, const char* usage) const {
        if (fields[0] != key) fail("expected '" + std::string(usage) + "', found " + quoted(fields[0]));
        if (this->count != numbers + 1)
            fail("expected " + std::to_string(numbers) + " numbers after '" + key + "' (" + usage + "), found " +
                 std::to_string(this->count - 1));
    }

    std::vector<std::string_view> fields;
    size_t count = 0;

private:
    static constexpr size_t kMaxFields = kCenterFields + 1;

    static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

    std::string_view bytes_;
    std::string name_;
    size_t pos_ = 0, number_ = 0;
};

std::string readHrbfFile(const std::string& path) {
    return readFileCapped(path, kMaxHrbfBytes,
                          "file is larger than " + std::to_string(kMaxHrbfBytes >> 30) +
                              " GiB, the limit for an HRBF model (docs/hrbf-format.md)");
}

// %.17g, without the C locale's say in the decimal point: 17 significant digits always read back to the
// same double.
void put(std::string& out, double v, char after = ' ') {
    char buf[32];
    auto result = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17);
    out.append(buf, result.ptr);
    out += after;
}

void put(std::string& out, const Eigen::Vector3d& v, char after = ' ') {
    put(out, v.x());
    put(out, v.y());
    put(out, v.z(), after);
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

// Every number parsed is finite, but together they may still be absurd: coefficients of 1e300 overflow f
// or grad f, and made-up coefficients do not interpolate the stored normals. A fitted model satisfies
// f(p_j) = 0 and grad f(p_j) = n_j to about 1e-6 (docs/fitting.md); a file that misses by far more than that
// was not written by a fit, and every later step (projection, normals, validate) would believe it.
//
// The checks that need no evaluation: the frame, and every centre inside the normalized box.
// Normalized coordinates: the fit's box is centred at the origin with a unit diagonal.
void checkInBox(const Eigen::Vector3d& centre, size_t j, const std::string& name) {
    if (!(centre.cwiseAbs().maxCoeff() <= 1.0))
        fail(name, "centre " + std::to_string(j + 1) +
                       " lies outside the normalized box (coordinates beyond +-1; the file is inconsistent)");
}

void checkFrame(const Surface& model, const std::string& name) {
    const double inverse = 1.0 / model.frame.scale;
    if (!std::isfinite(inverse) || !(model.frame.center.array().abs() + inverse).allFinite())
        fail(name, "the frame's scale " + number(model.frame.scale) +
                       " maps the model to a box too large to represent (the file is inconsistent)");
    for (size_t j = 0; j < model.size(); ++j) checkInBox(model.centers[j], j, name);
}

// The model must pass through its centres with their normals (evaluated: for a partition of unity, after the
// grid is built). Returns measureFit(model), which it computes on the way.
FitStats checkConsistent(const Surface& model, const std::string& name) {
    auto overflow = [&](size_t j) {
        fail(name, "centre " + std::to_string(j + 1) +
                       ": f or its gradient overflows there (coefficients too large; the file is inconsistent)");
    };
    auto badNormal = [&](size_t j) {
        fail(name, "centre " + std::to_string(j + 1) + ": the normal's length overflows (the file is inconsistent)");
    };
    auto mismatched = [&](size_t j, double mismatch) {
        fail(name, "centre " + std::to_string(j + 1) + ": |grad f - n| is " + number(mismatch) +
                       " of |n| (the limit is " + number(kMaxLoadedGradientMismatch) +
                       "); the stored normals disagree with grad f: the file is inconsistent");
    };
    FitStats stats;
    size_t firstMismatch = SIZE_MAX;
    double mismatchValue = 0;
    if (model.method == FitMethod::Global) {
        for (size_t j = 0; j < model.size(); ++j) {
            Eigen::Vector3d g;
            double f = model.eval(model.centers[j], g);
            if (!std::isfinite(f) || !g.allFinite() || !std::isfinite(g.norm())) overflow(j);
            if (!std::isfinite(model.normals[j].norm())) badNormal(j);
        }
        stats = measureFit(model);
        for (size_t j = 0; j < model.size() && firstMismatch == SIZE_MAX; ++j) {
            Eigen::Vector3d g;
            model.eval(model.centers[j], g);
            const Eigen::Vector3d& n = model.normals[j];
            double mismatch = (g - n).norm() / n.norm();
            if (!(mismatch <= kMaxLoadedGradientMismatch)) firstMismatch = j, mismatchValue = mismatch;
        }
    } else {
        // The partition of unity in one pass over all threads, in float as the device draws it (measureFit's
        // figures): at a million points the reader's checks are most of a load.
        const std::vector<Eigen::Vector4f> values = PuFloat(model.pu).evalMany(model.centers);
        struct Chunk {
            size_t overflow = SIZE_MAX, badNormal = SIZE_MAX, mismatch = SIZE_MAX;
            double mismatchValue = 0, maxDistance = 0, maxAngle = 0, sumDistance = 0;
        };
        std::vector<Chunk> chunks(64);
        const size_t used = parallelChunks(model.size(), 4096, [&](size_t begin, size_t end, size_t k) {
            Chunk& c = chunks[k];
            for (size_t j = begin; j < end; ++j) {
                const double f = values[j].w();
                const Eigen::Vector3d g = values[j].head<3>().cast<double>(), &n = model.normals[j];
                if (!std::isfinite(f) || !g.allFinite() || !std::isfinite(g.norm())) {
                    c.overflow = std::min(c.overflow, j);
                    continue;
                }
                if (!std::isfinite(n.norm())) {
                    c.badNormal = std::min(c.badNormal, j);
                    continue;
                }
                const double gn = g.norm();
                const double distance = gn > 0 ? std::abs(f) / gn : INFINITY;
                c.maxDistance = std::max(c.maxDistance, distance);
                c.sumDistance += distance;
                c.maxAngle = std::max(c.maxAngle, std::atan2(g.cross(n).norm(), g.dot(n)) * 180.0 / M_PI);
                const double mismatch = (g - n).norm() / n.norm();
                if (!(mismatch <= kMaxLoadedGradientMismatch) && c.mismatch == SIZE_MAX)
                    c.mismatch = j, c.mismatchValue = mismatch;
            }
        });
        size_t first = SIZE_MAX;
        bool firstIsNormal = false;
        stats.controlPoints = model.size();
        for (size_t k = 0; k < used; ++k) {
            const Chunk& c = chunks[k];
            if (std::min(c.overflow, c.badNormal) < first)
                first = std::min(c.overflow, c.badNormal), firstIsNormal = c.badNormal < c.overflow;
            if (c.mismatch < firstMismatch) firstMismatch = c.mismatch, mismatchValue = c.mismatchValue;
            stats.maxDistance = std::max(stats.maxDistance, c.maxDistance);
            stats.maxNormalAngleDeg = std::max(stats.maxNormalAngleDeg, c.maxAngle);
            stats.meanDistance += c.sumDistance;
        }
        stats.meanDistance /= double(std::max<size_t>(1, model.size()));
        if (first != SIZE_MAX) firstIsNormal ? badNormal(first) : overflow(first);
    }
    if (!(stats.maxDistance <= kMaxLoadedDistance))
        fail(name, "the model does not pass through its own centres: |f|/|grad f| reaches " +
                       number(stats.maxDistance) + " of the diagonal (a fit gives under 1e-6, the limit is " +
                       number(kMaxLoadedDistance) + "); the file is inconsistent");
    if (!(stats.maxNormalAngleDeg <= kMaxLoadedAngleDeg))
        fail(name, "the stored normals disagree with grad f at the centres by up to " +
                       number(stats.maxNormalAngleDeg) + " degrees (the limit is " + number(kMaxLoadedAngleDeg) +
                       "); the file is inconsistent");
    if (firstMismatch != SIZE_MAX) mismatched(firstMismatch, mismatchValue);
    return stats;
}

// A `key N` line: N in [lowest, highest], and no more than `bytes` can hold at `lineBytes` a line.
uint64_t countLine(Lines& lines, const char* key, const char* noun, uint64_t lowest, uint64_t highest, size_t lineBytes,
                   size_t bytes) {
    lines.expectKey(key, 1, (std::string(key) + " N").c_str());
    uint64_t m = 0;
    std::string_view count = lines.fields[1];
    auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), m);
    if (ec == std::errc::result_out_of_range || (ec == std::errc() && m > highest))
        lines.fail(quoted(count) + " " + noun + " is more than the maximum of " + std::to_string(highest));
    if (ec != std::errc() || end != count.data() + count.size())
        lines.fail(quoted(count) + " is not a count of " + noun);
    if (m < lowest) lines.fail(std::to_string(m) + " " + noun + ": a model has at least " + std::to_string(lowest));
    if (m * lineBytes > bytes)
        lines.fail(std::to_string(m) + " " + noun + " cannot fit in a file of " + std::to_string(bytes) +
                   " bytes (truncated?)");
    return m;
}

// ---- Version 3: binary

static_assert(std::endian::native == std::endian::little, "the .hrbf version 3 reader and writer assume little endian");

constexpr uint32_t kVersion3 = 3;
constexpr size_t kHeaderBytes = 128;
constexpr size_t kAlign = 64;        // every array starts at a multiple of 64 bytes
constexpr size_t kCentreBytes = 80;  // f64 x y z nx ny nz alpha bx by bz
constexpr size_t kPatchBytes = 32;   // f32 cx cy cz radius ax ay az b
constexpr size_t kCountBytes = 2;    // u16 nodes of a patch
constexpr size_t kNodeBytes = 28;    // f32 x y z alpha bx by bz (patch units)
constexpr size_t kPointBytes = 24;   // f32 x y z nx ny nz
constexpr size_t kSeedBytes = 24;    // f64 x y z
// A node's distance from its patch's centre, in patch units: below 1 in the fit, up to float rounding here.
constexpr double kNodeBallSlack = 1e-6;

// The header (docs/hrbf-format.md): offsets of its fields.
struct Header3 {
    uint32_t version = kVersion3, method = 0;
    uint64_t fileBytes = 0;
    uint32_t checksum = 0, headerBytes = kHeaderBytes;
    uint32_t points = 0, farField = 0, patches = 0, nodes = 0, seeds = 0, reserved = 0;
    double frame[4] = {}, tau = 0, linear[4] = {};
};
constexpr size_t kOffVersion = 8, kOffMethod = 12, kOffFileBytes = 16, kOffHeaderBytes = 28, kOffCounts = 32,
                 kOffFrame = 56, kOffTau = 88, kOffLinear = 96;

// The arrays' offsets and the file's size, from the counts (64-bit: a hostile count cannot wrap).
struct Layout3 {
    uint64_t centres = 0, patches = 0, counts = 0, nodes = 0, points = 0, seeds = 0, end = 0;
    explicit Layout3(const Header3& h) {
        const bool pu = h.method == 2;
        const uint64_t centreCount = pu ? h.farField : h.points;
        uint64_t at = kHeaderBytes;
        auto take = [&](uint64_t count, uint64_t bytes) {
            uint64_t start = at;
            at = (at + count * bytes + kAlign - 1) / kAlign * kAlign;
            return start;
        };
        centres = take(centreCount, kCentreBytes);
        if (pu) {
            patches = take(h.patches, kPatchBytes);
            counts = take(h.patches, kCountBytes);
            nodes = take(h.nodes, kNodeBytes);
            points = take(h.points, kPointBytes);
        }
        seeds = take(h.seeds, kSeedBytes);
        end = at;
    }
};

template <class T>
void store(std::string& out, size_t at, T v) {
    std::memcpy(out.data() + at, &v, sizeof v);
}
template <class T>
T fetch(const std::string& in, size_t at) {
    T v;
    std::memcpy(&v, in.data() + at, sizeof v);
    return v;
}

std::string encode3(const Surface& model) {
    const bool pu = model.method == FitMethod::PartitionOfUnity;
    Header3 h;
    h.method = pu ? 2 : 1;
    h.points = uint32_t(model.size());
    h.farField = pu ? uint32_t(model.pu.coarse.size()) : 0;
    h.patches = pu ? uint32_t(model.pu.patches.size()) : 0;
    h.nodes = pu ? uint32_t(model.pu.nodes.size()) : 0;
    h.seeds = uint32_t(model.seeds.size());
    const Hrbf& global = pu ? model.pu.coarse : model.global;
    Layout3 layout(h);
    std::string out(layout.end, '\0');
    out.replace(0, kHrbf3Magic.size(), kHrbf3Magic);
    store(out, kOffVersion, h.version);
    store(out, kOffMethod, h.method);
    store(out, kOffFileBytes, uint64_t(layout.end));
    store(out, kOffHeaderBytes, h.headerBytes);
    const uint32_t counts[6] = {h.points, h.farField, h.patches, h.nodes, h.seeds, 0};
    std::memcpy(out.data() + kOffCounts, counts, sizeof counts);
    const double frame[4] = {model.frame.center.x(), model.frame.center.y(), model.frame.center.z(), model.frame.scale};
    std::memcpy(out.data() + kOffFrame, frame, sizeof frame);
    store(out, kOffTau, pu ? model.pu.tau : 0.0);
    const double linear[4] = {global.a.x(), global.a.y(), global.a.z(), global.b};
    std::memcpy(out.data() + kOffLinear, linear, sizeof linear);

    const std::vector<Eigen::Vector3d>& normals = pu ? global.normals : model.normals;
    for (size_t j = 0; j < global.size(); ++j) {
        const double c[10] = {global.centers[j].x(), global.centers[j].y(), global.centers[j].z(), normals[j].x(),
                              normals[j].y(),        normals[j].z(),        global.alpha[j],       global.beta[j].x(),
                              global.beta[j].y(),    global.beta[j].z()};
        std::memcpy(out.data() + layout.centres + j * kCentreBytes, c, sizeof c);
    }
    if (pu) {
        const PuHrbf& m = model.pu;
        for (size_t i = 0; i < m.patches.size(); ++i) {
            const PuPatch& p = m.patches[i];
            const float f[8] = {float(p.center.x()), float(p.center.y()), float(p.center.z()), float(p.radius),
                                float(p.a.x()),      float(p.a.y()),      float(p.a.z()),      float(p.b)};
            std::memcpy(out.data() + layout.patches + i * kPatchBytes, f, sizeof f);
            store(out, layout.counts + i * kCountBytes, uint16_t(std::min<uint32_t>(p.count, UINT16_MAX)));
        }
        for (size_t k = 0; k < m.nodes.size(); ++k) {
            const PuNode& n = m.nodes[k];
            const float f[7] = {float(n.p.x()),    float(n.p.y()),    float(n.p.z()),   float(n.alpha),
                                float(n.beta.x()), float(n.beta.y()), float(n.beta.z())};
            std::memcpy(out.data() + layout.nodes + k * kNodeBytes, f, sizeof f);
        }
        for (size_t j = 0; j < model.size(); ++j) {
            const float f[6] = {float(model.centers[j].x()), float(model.centers[j].y()), float(model.centers[j].z()),
                                float(model.normals[j].x()), float(model.normals[j].y()), float(model.normals[j].z())};
            std::memcpy(out.data() + layout.points + j * kPointBytes, f, sizeof f);
        }
    }
    for (size_t s = 0; s < model.seeds.size(); ++s) {
        const double d[3] = {model.seeds[s].x(), model.seeds[s].y(), model.seeds[s].z()};
        std::memcpy(out.data() + layout.seeds + s * kSeedBytes, d, sizeof d);
    }
    store(out, kHrbf3ChecksumOffset, crc32c(out));  // computed with the field still 0
    return out;
}

// Reads version 3. With `evaluate` false only what needs no evaluation is checked (the writer's own check), and
// the patches, nodes and points are checked where they lie, not copied out: at a million points that copy is
// 0.6 GB and most of a save's time.
Surface decode3(const std::string& bytes, const std::string& name, bool evaluate, FitStats* measured) {
    auto bad = [&](const std::string& what) { fail(name, what); };
    if (bytes.size() < kHeaderBytes)
        bad("truncated: " + std::to_string(bytes.size()) + " bytes, shorter than the 128-byte version 3 header");
    Header3 h;
    h.version = fetch<uint32_t>(bytes, kOffVersion);
    if (h.version != kVersion3)
        bad("unsupported binary version " + std::to_string(h.version) + " (this build reads versions 1, 2 and 3)");
    h.fileBytes = fetch<uint64_t>(bytes, kOffFileBytes);
    if (h.fileBytes != bytes.size())
        bad("the header declares " + std::to_string(h.fileBytes) + " bytes but the file has " +
            std::to_string(bytes.size()) + (h.fileBytes > bytes.size() ? " (truncated)" : " (data after the end)"));
    h.checksum = fetch<uint32_t>(bytes, kHrbf3ChecksumOffset);
    const uint32_t zero = 0;
    uint32_t crc = crc32c(std::string_view(bytes).substr(0, kHrbf3ChecksumOffset));
    crc = crc32c(std::string_view(reinterpret_cast<const char*>(&zero), 4), crc);
    crc = crc32c(std::string_view(bytes).substr(kHrbf3ChecksumOffset + 4), crc);
    if (crc != h.checksum) {
        char text[96];
        std::snprintf(text, sizeof text, "checksum mismatch (stored %08x, computed %08x): the file is corrupt",
                      h.checksum, crc);
        bad(text);
    }
    h.method = fetch<uint32_t>(bytes, kOffMethod);
    h.headerBytes = fetch<uint32_t>(bytes, kOffHeaderBytes);
    uint32_t counts[6];
    std::memcpy(counts, bytes.data() + kOffCounts, sizeof counts);
    h.points = counts[0], h.farField = counts[1], h.patches = counts[2], h.nodes = counts[3], h.seeds = counts[4];
    h.reserved = counts[5];
    std::memcpy(h.frame, bytes.data() + kOffFrame, sizeof h.frame);
    h.tau = fetch<double>(bytes, kOffTau);
    std::memcpy(h.linear, bytes.data() + kOffLinear, sizeof h.linear);
    if (h.method != 1 && h.method != 2)
        bad("unknown model kind " + std::to_string(h.method) + " (1: the global fit, 2: the partition of unity)");
    if (h.headerBytes != kHeaderBytes || h.reserved != 0)
        bad("the header's size or reserved field is not version 3's (" + std::to_string(h.headerBytes) + ", " +
            std::to_string(h.reserved) + ")");
    const bool pu = h.method == 2;
    auto range = [&](const char* what, uint64_t n, uint64_t lowest, uint64_t highest) {
        if (n < lowest || n > highest)
            bad(std::to_string(n) + " " + what + ": a model holds " + std::to_string(lowest) + " to " +
                std::to_string(highest));
    };
    if (pu) {
        range("points", h.points, 2, UINT32_MAX);
        range("far-field centres", h.farField, 2, kMaxControlPoints);
        range("patches", h.patches, 1, UINT32_MAX);
        range("nodes", h.nodes, 1, UINT32_MAX);
    } else {
        range("centres", h.points, 2, kMaxControlPoints);
        if (h.farField || h.patches || h.nodes) bad("a global model with far-field centres, patches or nodes");
    }
    range("seeds", h.seeds, 1, kMaxSeeds);
    const Layout3 layout(h);
    if (layout.end != bytes.size())
        bad("the counts (" + std::to_string(h.points) + " points, " + std::to_string(h.patches) + " patches, " +
            std::to_string(h.nodes) + " nodes) need " + std::to_string(layout.end) + " bytes, the file has " +
            std::to_string(bytes.size()));
    // Padding is zero, so that a model has one encoding.
    auto zeroFrom = [&](uint64_t from, uint64_t to, const char* after) {
        for (uint64_t k = from; k < to; ++k)
            if (bytes[k] != 0) bad(std::string("non-zero padding after the ") + after);
    };
    const uint64_t centreCount = pu ? h.farField : h.points;
    zeroFrom(layout.centres + centreCount * kCentreBytes, pu ? layout.patches : layout.seeds, "centres");
    if (pu) {
        zeroFrom(layout.patches + uint64_t(h.patches) * kPatchBytes, layout.counts, "patches");
        zeroFrom(layout.counts + uint64_t(h.patches) * kCountBytes, layout.nodes, "node counts");
        zeroFrom(layout.nodes + uint64_t(h.nodes) * kNodeBytes, layout.points, "nodes");
        zeroFrom(layout.points + uint64_t(h.points) * kPointBytes, layout.seeds, "points");
    }
    zeroFrom(layout.seeds + uint64_t(h.seeds) * kSeedBytes, layout.end, "seeds");

    auto finite = [&](const auto* v, size_t n, const std::string& where) {
        for (size_t k = 0; k < n; ++k)
            if (!std::isfinite(v[k])) bad(where + ": a value is not finite");
    };
    Surface model;
    finite(h.frame, 4, "the frame");
    model.frame.center = {h.frame[0], h.frame[1], h.frame[2]};
    model.frame.scale = h.frame[3];
    if (!(model.frame.scale > 0)) bad("the frame's scale must be positive");
    finite(h.linear, 4, "the linear term");
    Hrbf& global = pu ? model.pu.coarse : model.global;
    global.a = {h.linear[0], h.linear[1], h.linear[2]};
    global.b = h.linear[3];
    global.centers.resize(centreCount);
    global.normals.resize(centreCount);
    global.alpha.resize(centreCount);
    global.beta.resize(centreCount);
    const char* centreName = pu ? "far-field centre " : "centre ";
    for (size_t j = 0; j < centreCount; ++j) {
        double c[10];
        std::memcpy(c, bytes.data() + layout.centres + j * kCentreBytes, sizeof c);
        finite(c, 10, centreName + std::to_string(j + 1));
        global.centers[j] = {c[0], c[1], c[2]};
        global.normals[j] = {c[3], c[4], c[5]};
        global.alpha[j] = c[6];
        global.beta[j] = {c[7], c[8], c[9]};
        if (global.normals[j].squaredNorm() == 0) bad(centreName + std::to_string(j + 1) + ": normal is zero");
    }
    if (pu) {
        PuHrbf& m = model.pu;
        finite(&h.tau, 1, "tau");
        m.tau = h.tau;
        if (!(m.tau > 0 && m.tau < 1)) bad("tau must be in (0, 1)");
        if (evaluate) m.patches.resize(h.patches);
        uint64_t total = 0;
        for (size_t i = 0; i < h.patches; ++i) {
            float f[8];
            std::memcpy(f, bytes.data() + layout.patches + i * kPatchBytes, sizeof f);
            auto where = [i] { return "patch " + std::to_string(i + 1); };
            if (!Eigen::Matrix<float, 8, 1>::Map(f).allFinite()) bad(where() + ": a value is not finite");
            PuPatch p;
            p.center = {f[0], f[1], f[2]};
            p.radius = f[3];
            p.a = {f[4], f[5], f[6]};
            p.b = f[7];
            const uint16_t count = fetch<uint16_t>(bytes, layout.counts + i * kCountBytes);
            if (count < 1 || count > kMaxPatchNodes)
                bad(where() + ": " + std::to_string(count) + " is not a patch's node count (1 to " +
                    std::to_string(kMaxPatchNodes) + "; a fit makes 12 to a few dozen)");
            if (!(p.radius > 0 && p.radius <= 4)) bad(where() + ": a patch's radius must be in (0, 4]");
            if (!(p.center.cwiseAbs().maxCoeff() <= 4))
                bad(where() + ": the patch's centre lies far outside the model");
            p.first = uint32_t(std::min<uint64_t>(total, UINT32_MAX));
            p.count = count;
            total += count;
            if (evaluate) m.patches[i] = p;
        }
        if (total != h.nodes) bad(std::to_string(h.nodes) + " nodes, but the patches hold " + std::to_string(total));
        if (evaluate) m.nodes.resize(h.nodes);
        for (size_t k = 0; k < h.nodes; ++k) {
            float f[7];
            std::memcpy(f, bytes.data() + layout.nodes + k * kNodeBytes, sizeof f);
            if (!Eigen::Matrix<float, 7, 1>::Map(f).allFinite())
                bad("node " + std::to_string(k + 1) + ": a value is not finite");
            const Eigen::Vector3d p(f[0], f[1], f[2]);
            if (!(p.norm() <= 1 + kNodeBallSlack))
                bad("node " + std::to_string(k + 1) + ": it lies outside its patch (patch units beyond 1)");
            if (evaluate) m.nodes[k] = {p, f[3], {f[4], f[5], f[6]}};
        }
        if (evaluate) model.centers.resize(h.points), model.normals.resize(h.points);
        for (size_t j = 0; j < h.points; ++j) {
            float f[6];
            std::memcpy(f, bytes.data() + layout.points + j * kPointBytes, sizeof f);
            if (!Eigen::Matrix<float, 6, 1>::Map(f).allFinite())
                bad("point " + std::to_string(j + 1) + ": a value is not finite");
            const Eigen::Vector3d centre(f[0], f[1], f[2]), normal(f[3], f[4], f[5]);
            if (normal.squaredNorm() == 0) bad("point " + std::to_string(j + 1) + ": normal is zero");
            if (evaluate)
                model.centers[j] = centre, model.normals[j] = normal;
            else
                checkInBox(centre, j, name);  // checkFrame's check, for the points not kept
        }
    } else {
        if (h.tau != 0) bad("tau must be 0 for a global model");
        model.method = FitMethod::Global;
        model.centers = global.centers;
        model.normals = global.normals;
    }
    model.seeds.resize(h.seeds);
    for (size_t s = 0; s < model.seeds.size(); ++s) {
        double d[3];
        std::memcpy(d, bytes.data() + layout.seeds + s * kSeedBytes, sizeof d);
        finite(d, 3, "seed " + std::to_string(s + 1));
        model.seeds[s] = {d[0], d[1], d[2]};
        if (!(model.seeds[s].cwiseAbs().maxCoeff() <= 4))
            bad("seed " + std::to_string(s + 1) + " lies far outside the model");
    }
    checkFrame(model, name);
    if (!evaluate) return model;
    if (pu) model.pu.grid = buildPuGrid(model.pu.patches);
    FitStats stats = checkConsistent(model, name);
    if (measured) *measured = stats;
    return model;
}

}  // namespace

std::string encodeHrbf(const Surface& model, HrbfFormat format) {
    const size_t m = model.size();
    const bool global = model.method == FitMethod::Global;
    if (model.normals.size() != m ||
        (global && (model.global.size() != m || model.global.alpha.size() != m || model.global.beta.size() != m)))
        throw Error("the model is incomplete (" + std::to_string(m) + " centres, " +
                    std::to_string(model.normals.size()) + " normals)");
    if (m < 2 || (global && m > kMaxControlPoints))
        throw Error(std::to_string(m) + " centres (a global .hrbf file holds 2 to " +
                    std::to_string(kMaxControlPoints) + ")");
    if (!global && m > UINT32_MAX) throw Error(std::to_string(m) + " points: a .hrbf file holds at most 2^32 - 1");

    if (format == HrbfFormat::Binary) {
        std::string bytes;
        if (model.seeds.empty()) {  // a model built in memory without them: the reader's choice
            Surface seeded = model;
            chooseSeeds(seeded);
            bytes = encode3(seeded);
        } else {
            bytes = encode3(model);
        }
        // What needs no evaluation (the model was fitted or read already): a coefficient beyond float's range
        // or a zero normal would make a file that cannot be loaded, and it is better to learn that now.
        decode3(bytes, "the model", false, nullptr);
        return bytes;
    }

    std::string text = std::string(kMagic) + " " + (global ? "1" : "2") + "\n";
    text +=
        "# Inkwell HRBF model (docs/hrbf-format.md); coordinates are normalized: x_normalized = "
        "(x_input - center) * scale\n";
    auto centreLines = [&](const Hrbf& h, const std::vector<Eigen::Vector3d>& normals) {
        text += "linear ";
        put(text, h.a);
        put(text, h.b, '\n');
        text += "# x y z nx ny nz alpha beta_x beta_y beta_z\n";
        for (size_t j = 0; j < h.size(); ++j) {
            put(text, h.centers[j]);
            put(text, normals[j]);
            put(text, h.alpha[j]);
            put(text, h.beta[j], '\n');
        }
    };
    if (global) {
        text += "centers " + std::to_string(m) + "\n";
        text += "frame ";
        put(text, model.frame.center);
        put(text, model.frame.scale, '\n');
        centreLines(model.global, model.normals);
    } else {
        const PuHrbf& pu = model.pu;
        text += "points " + std::to_string(m) + "\n";
        text += "frame ";
        put(text, model.frame.center);
        put(text, model.frame.scale, '\n');
        text += "tau ";
        put(text, pu.tau, '\n');
        text += "coarse " + std::to_string(pu.coarse.size()) + "\n";
        centreLines(pu.coarse, pu.coarse.normals);
        text += "patches " + std::to_string(pu.patches.size()) + "\n# cx cy cz radius ax ay az b nodes\n";
        for (const PuPatch& p : pu.patches) {
            put(text, p.center);
            put(text, p.radius);
            put(text, p.a);
            put(text, p.b);
            text += std::to_string(p.count) + "\n";
        }
        text += "nodes " + std::to_string(pu.nodes.size()) + "\n# x y z alpha beta_x beta_y beta_z (patch units)\n";
        for (const PuNode& n : pu.nodes) {
            put(text, n.p);
            put(text, n.alpha);
            put(text, n.beta, '\n');
        }
        text += "# the interpolated points: x y z nx ny nz\n";
        for (size_t j = 0; j < m; ++j) {
            put(text, model.centers[j]);
            put(text, model.normals[j], '\n');
        }
    }
    text += "end\n";

    // Check what we wrote with the reader: a non-finite coefficient or a zero normal would make a file that
    // cannot be loaded, and it is better to learn that now.
    parseHrbf(text, "the model");
    return text;
}

void saveHrbf(const std::string& path, const Surface& model, HrbfFormat format) {
    std::string text;
    try {
        text = encodeHrbf(model, format);
    } catch (const Error& e) {
        throw Error("cannot save '" + path + "': " + e.what());
    }
    writeAtomically(path, [&](const std::string& tmp) {
        std::FILE* file = std::fopen(tmp.c_str(), "wb");
        if (!file) throw Error("cannot write '" + path + "': " + std::strerror(errno));
        bool ok = std::fwrite(text.data(), 1, text.size(), file) == text.size();
        int error = errno;
        if (std::fclose(file) != 0 && ok) {
            ok = false;
            error = errno;
        }
        if (!ok) throw Error("cannot write '" + path + "': " + std::strerror(error));
    });
}

Surface loadHrbf(const std::string& path, FitStats* measured) { return parseHrbf(readHrbfFile(path), path, measured); }

Surface parseHrbf(const std::string& bytes, const std::string& name, FitStats* measured) {
    if (bytes.compare(0, kHrbf3Magic.size(), kHrbf3Magic) == 0) return decode3(bytes, name, true, measured);
    Lines lines(bytes, name);
    const std::string magicLine = std::string(kMagic) + " 1' or '" + kMagic + " 2";
    if (!lines.next()) fail(name, "empty file: not an Inkwell HRBF model (expected '" + magicLine + "' on line 1)");
    if (lines.line() != 1)
        fail(name, "line 1: not an Inkwell HRBF model (expected '" + magicLine + "' as the first line)");
    if (lines.fields[0] != kMagic)
        lines.fail("not an Inkwell HRBF model (expected '" + magicLine + "', found " + quoted(lines.fields[0]) + ")");
    if (lines.count != 2 || (lines.fields[1] != "1" && lines.fields[1] != "2"))
        lines.fail("unsupported version " + (lines.count > 1 ? quoted(lines.fields[1]) : "(none)") +
                   " (this build reads versions 1 and " + std::to_string(kVersion) + ")");
    const bool global = lines.fields[1] == "1";

    auto need = [&](const char* what) {
        if (!lines.next()) fail(name, std::string("truncated: the file ends before ") + what);
    };
    // `linear` and m centre lines of a global HRBF (the model, or the partition of unity's far field).
    auto readCentres = [&](Hrbf& h, uint64_t m, const char* what) {
        need("the 'linear' line");
        lines.expectKey("linear", 4, "linear ax ay az b");
        h.a = lines.vector(1);
        h.b = lines.real(4);
        for (uint64_t j = 0; j < m; ++j) {
            if (!lines.next()) fail(name, "truncated: " + std::to_string(j) + " of " + std::to_string(m) + " " + what);
            if (lines.fields[0] == "end")
                lines.fail("'end' after " + std::to_string(j) + " of the " + std::to_string(m) + " " + what +
                           " declared");
            if (lines.count != kCenterFields)
                lines.fail("expected 10 numbers (x y z nx ny nz alpha bx by bz), found " + std::to_string(lines.count) +
                           " fields");
            h.centers.push_back(lines.vector(0));
            h.normals.push_back(lines.vector(3));
            h.alpha.push_back(lines.real(6));
            h.beta.push_back(lines.vector(7));
            if (h.normals.back().squaredNorm() == 0) lines.fail("normal is zero");
        }
    };
    auto readFrame = [&](Surface& s) {
        need("the 'frame' line");
        lines.expectKey("frame", 4, "frame cx cy cz scale");
        s.frame.center = lines.vector(1);
        s.frame.scale = lines.real(4);
        if (!(s.frame.scale > 0)) lines.fail("the frame's scale must be positive");
    };

    Surface model;
    uint64_t m = 0;
    if (global) {
        model.method = FitMethod::Global;
        need("the 'centers' line");
        m = countLine(lines, "centers", "centres", 2, kMaxControlPoints, kMinCenterLineBytes, bytes.size());
        readFrame(model);
        readCentres(model.global, m, "centres");
        model.centers = model.global.centers;
        model.normals = model.global.normals;
    } else {
        PuHrbf& pu = model.pu;
        need("the 'points' line");
        m = countLine(lines, "points", "points", 2, UINT32_MAX, 12, bytes.size());
        readFrame(model);
        need("the 'tau' line");
        lines.expectKey("tau", 1, "tau t");
        pu.tau = lines.real(1);
        if (!(pu.tau > 0 && pu.tau < 1)) lines.fail("tau must be in (0, 1)");
        need("the 'coarse' line");
        uint64_t coarse =
            countLine(lines, "coarse", "far-field centres", 2, kMaxControlPoints, kMinCenterLineBytes, bytes.size());
        readCentres(pu.coarse, coarse, "far-field centres");
        need("the 'patches' line");
        uint64_t patches = countLine(lines, "patches", "patches", 1, UINT32_MAX, 18, bytes.size());
        uint64_t total = 0;
        for (uint64_t i = 0; i < patches; ++i) {
            if (!lines.next())
                fail(name, "truncated: " + std::to_string(i) + " of " + std::to_string(patches) + " patches");
            if (lines.count != 9)
                lines.fail("expected 9 fields (cx cy cz radius ax ay az b nodes), found " +
                           std::to_string(lines.count));
            PuPatch p;
            p.center = lines.vector(0);
            p.radius = lines.real(3);
            p.a = lines.vector(4);
            p.b = lines.real(7);
            uint64_t count = 0;
            std::string_view c = lines.fields[8];
            auto [end, ec] = std::from_chars(c.data(), c.data() + c.size(), count);
            if (ec != std::errc() || end != c.data() + c.size() || count < 1 || count > kMaxPatchNodes)
                lines.fail(quoted(c) + " is not a patch's node count (1 to " + std::to_string(kMaxPatchNodes) +
                           "; a fit makes 12 to a few dozen)");
            if (!(p.radius > 0 && p.radius <= 4)) lines.fail("a patch's radius must be in (0, 4]");
            if (!(p.center.cwiseAbs().maxCoeff() <= 4)) lines.fail("the patch's centre lies far outside the model");
            p.first = uint32_t(total);
            p.count = uint32_t(count);
            total += count;
            if (total > UINT32_MAX) lines.fail("more nodes than a model holds");
            pu.patches.push_back(p);
        }
        need("the 'nodes' line");
        uint64_t nodes = countLine(lines, "nodes", "nodes", 1, UINT32_MAX, 14, bytes.size());
        if (nodes != total) lines.fail(std::to_string(nodes) + " nodes, but the patches hold " + std::to_string(total));
        pu.nodes.resize(nodes);
        for (PuNode& n : pu.nodes) {
            if (!lines.next()) fail(name, "truncated: the file ends inside the nodes");
            if (lines.count != 7)
                lines.fail("expected 7 numbers (x y z alpha bx by bz), found " + std::to_string(lines.count));
            n.p = lines.vector(0);
            n.alpha = lines.real(3);
            n.beta = lines.vector(4);
            if (!(n.p.norm() <= 1 + 1e-9)) lines.fail("a node lies outside its patch (patch units beyond 1)");
        }
        for (uint64_t j = 0; j < m; ++j) {
            if (!lines.next()) fail(name, "truncated: " + std::to_string(j) + " of " + std::to_string(m) + " points");
            if (lines.count != 6)
                lines.fail("expected 6 numbers (x y z nx ny nz), found " + std::to_string(lines.count));
            model.centers.push_back(lines.vector(0));
            model.normals.push_back(lines.vector(3));
            if (model.normals.back().squaredNorm() == 0) lines.fail("normal is zero");
        }
    }
    if (!lines.next()) fail(name, "truncated: no 'end' line after the " + std::to_string(m) + " centres");
    if (lines.fields[0] != "end" || lines.count != 1)
        lines.fail("expected 'end' after the " + std::to_string(m) + " centres declared, found " +
                   quoted(lines.fields[0]) + " (more centres than the count?)");
    if (lines.next()) lines.fail("unexpected " + quoted(lines.fields[0]) + " after 'end'");
    // The grid only once the whole file has been read and checked, all that needs no evaluation; buildPuGrid
    // bounds its size whatever the patches' radii.
    checkFrame(model, name);
    if (!global) model.pu.grid = buildPuGrid(model.pu.patches);
    chooseSeeds(model);
    FitStats stats = checkConsistent(model, name);
    if (measured) *measured = stats;
    return model;
}

}  // namespace ink
