#include "hrbf_io.h"

#include "common.h"
#include "files.h"
#include "surface.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string_view>
#include <utility>
#include <vector>

namespace ink {
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

std::string readFile(const std::string& path) {
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
void checkFrame(const Surface& model, const std::string& name) {
    const double inverse = 1.0 / model.frame.scale;
    if (!std::isfinite(inverse) || !(model.frame.center.array().abs() + inverse).allFinite())
        fail(name, "the frame's scale " + number(model.frame.scale) +
                       " maps the model to a box too large to represent (the file is inconsistent)");
    // Normalized coordinates: the fit's box is centred at the origin with a unit diagonal.
    for (size_t j = 0; j < model.size(); ++j)
        if (!(model.centers[j].cwiseAbs().maxCoeff() <= 1.0))
            fail(name, "centre " + std::to_string(j + 1) +
                           " lies outside the normalized box (coordinates beyond +-1; the file is inconsistent)");
}

// The model must pass through its centres with their normals (evaluated: for a partition of unity, after the
// grid is built).
void checkConsistent(const Surface& model, const std::string& name) {
    for (size_t j = 0; j < model.size(); ++j) {
        Eigen::Vector3d g;
        double f = model.eval(model.centers[j], g);
        if (!std::isfinite(f) || !g.allFinite() || !std::isfinite(g.norm()))
            fail(name, "centre " + std::to_string(j + 1) +
                           ": f or its gradient overflows there (coefficients too large; the file is inconsistent)");
        const Eigen::Vector3d& n = model.normals[j];
        if (!std::isfinite(n.norm()))
            fail(name,
                 "centre " + std::to_string(j + 1) + ": the normal's length overflows (the file is inconsistent)");
    }
    FitStats stats = measureFit(model);
    if (!(stats.maxDistance <= kMaxLoadedDistance))
        fail(name, "the model does not pass through its own centres: |f|/|grad f| reaches " +
                       number(stats.maxDistance) + " of the diagonal (a fit gives under 1e-6, the limit is " +
                       number(kMaxLoadedDistance) + "); the file is inconsistent");
    if (!(stats.maxNormalAngleDeg <= kMaxLoadedAngleDeg))
        fail(name, "the stored normals disagree with grad f at the centres by up to " +
                       number(stats.maxNormalAngleDeg) + " degrees (the limit is " + number(kMaxLoadedAngleDeg) +
                       "); the file is inconsistent");
    for (size_t j = 0; j < model.size(); ++j) {
        Eigen::Vector3d g;
        model.eval(model.centers[j], g);
        const Eigen::Vector3d& n = model.normals[j];
        double mismatch = (g - n).norm() / n.norm();
        if (!(mismatch <= kMaxLoadedGradientMismatch))
            fail(name, "centre " + std::to_string(j + 1) + ": |grad f - n| is " + number(mismatch) +
                           " of |n| (the limit is " + number(kMaxLoadedGradientMismatch) +
                           "); the stored normals disagree with grad f: the file is inconsistent");
    }
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

}  // namespace

void saveHrbf(const std::string& path, const Surface& model) {
    const size_t m = model.size();
    const bool global = model.method == FitMethod::Global;
    if (model.normals.size() != m ||
        (global && (model.global.size() != m || model.global.alpha.size() != m || model.global.beta.size() != m)))
        throw Error("cannot save '" + path + "': the model is incomplete (" + std::to_string(m) + " centres, " +
                    std::to_string(model.normals.size()) + " normals)");
    if (m < 2 || (global && m > kMaxControlPoints))
        throw Error("cannot save '" + path + "': " + std::to_string(m) + " centres (a global .hrbf file holds 2 to " +
                    std::to_string(kMaxControlPoints) + ")");

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
    try {
        parseHrbf(text, "the model");
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

Surface loadHrbf(const std::string& path) { return parseHrbf(readFile(path), path); }

Surface parseHrbf(const std::string& bytes, const std::string& name) {
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
                           "; a fit makes 8 to 24)");
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
    checkConsistent(model, name);
    return model;
}

}  // namespace ink
