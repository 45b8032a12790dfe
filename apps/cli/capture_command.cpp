// capture (frames along an orbit, with a manifest) and compare (two PNGs against a tolerance): the tools of
// visual regression testing (docs/capture.md).
#include "commands.h"

#include <unistd.h>
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <system_error>

namespace app {

namespace {

using ordered = nlohmann::ordered_json;  // the manifest keeps its keys in a readable order

constexpr uint32_t kMaxFrames = 10000;  // frame_0000 .. frame_9999

struct CaptureOptions {
    uint32_t frames = 0;
    float orbitDeg = 360.0f;
    std::string directory;
};

struct CompareOptions {
    std::string a, b, diff;
    unsigned threshold = inkwell::kCompareThreshold;
    double maxFraction = inkwell::kCompareMaxFraction;
};

const char* directionName(inkwell::DirectionField d) {
    if (d == inkwell::DirectionField::Axis) return "axis";
    return d == inkwell::DirectionField::CurvatureMin ? "curvature-min" : "curvature-max";
}

// The float as the double with its shortest decimal form: 1.6f is written 1.6, not 1.600000023841858.
double shortest(float v) {
    char text[32];
    char* end = std::to_chars(text, text + sizeof text, v).ptr;
    double d = v;
    std::from_chars(text, end, d);
    return d;
}

ordered vec3Json(const std::array<float, 3>& v) { return {shortest(v[0]), shortest(v[1]), shortest(v[2])}; }

// Everything that decides the pixels, so that a capture can be repeated from its manifest.
ordered parametersJson(const Options& o, size_t controlPoints, uint32_t passes, const CaptureOptions& c) {
    const inkwell::DrawingOptions& r = o.drawing;
    const inkwell::Look& s = o.look;
    return {{"control_points", controlPoints},
            {"levels", r.levels},
            {"passes", passes},
            {"distribution", o.distribution},
            {"candidates_per_stipple", shortest(r.candidatesPerStipple)},
            {"style", inkwell::styleName(r.style)},
            {"direction", directionName(r.direction)},
            {"axis", {r.axis[0], r.axis[1], r.axis[2]}},
            {"seeds", r.gridSeeds ? "grid" : "control"},
            {"grid", r.grid},
            {"rho", r.rho},
            {"seed", r.seed},
            {"keep_levels", o.keepLevels},
            {"size", o.size},
            {"supersample", s.supersample},
            {"orbit_deg", shortest(c.orbitDeg)},
            {"tau", shortest(s.tau)},
            {"tone", shortest(s.toneGamma)},
            {"ink_density", shortest(s.inkDensity)},
            {"dot_size", shortest(s.dotSize)},
            {"silhouette_size", shortest(s.silhouetteSize)},
            {"hidden_lines", s.hiddenLines},
            {"occlusion", s.occlusion},
            {"screen_spacing", s.screenSpacing},
            {"ink", o.ink},
            {"paper", o.paper},
            {"light", vec3Json(s.light)},
            {"light_follows_camera", s.lightFollowsCamera},
            {"up", inkwell::upName(o.up)}};
}

ordered cameraJson(const inkwell::Camera& c) {
    return {{"azimuth_deg", shortest(c.azimuthDeg)},
            {"elevation_deg", shortest(c.elevationDeg)},
            {"distance", shortest(c.distance)},
            {"target", vec3Json(c.target)}};
}

void writeOrdered(const std::string& path, const ordered& j) {
    inkwell::writeFileAtomically(path, j.dump(2) + "\n");  // every write and the close checked
}

// The output directory of one capture: created (with missing parents) up front, so that a bad path fails
// before any work. The frames are drawn into a staging directory inside it (`.inkwell-capture-XXXXXX`, on the
// same file system), and only when all are drawn does commit() swap them in: the old manifest removed, each
// frame renamed into place (a rename replaces the directory entry: a symbolic link there is replaced, never
// written through), the frames of the old manifest that the new capture does not have removed, then the new
// manifest (and stats) renamed into place by the caller's OutputBatch. Unless commit() ran, the destructor
// removes the staging directory and the directories it created: a failed capture leaves the old capture, its
// manifest and frames, as they were. A signal's handler removes the staging directory too (files.h).
class CaptureOutput {
public:
    explicit CaptureOutput(const std::string& path) : path_(path) {
        namespace fs = std::filesystem;
        std::error_code error;
        for (fs::path p = fs::path(path).lexically_normal(); !p.empty() && !fs::exists(p, error); p = p.parent_path()) {
            created_.push_back(p);
            if (p == p.parent_path()) break;
        }
        fs::create_directories(path, error);
        if (error) {
            removeCreated();
            throw inkwell::Error("cannot create directory '" + path + "': " + error.message());
        }
        if (!fs::is_directory(path, error))
            throw inkwell::Error("cannot create directory '" + path + "': a file of that name exists");
    }
    ~CaptureOutput() {
        std::error_code error;
        if (!staging_.empty()) std::filesystem::remove_all(staging_, error);
        inkwell::unregisterTemporary(stagingSlot_);
        if (!committed_) removeCreated();
    }
    CaptureOutput(const CaptureOutput&) = delete;
    CaptureOutput& operator=(const CaptureOutput&) = delete;

    // The staging directory, made on first use.
    const std::string& staging() {
        if (staging_.empty()) {
            std::string pattern = (std::filesystem::path(path_) / ".inkwell-capture-XXXXXX").string();
            if (!::mkdtemp(pattern.data()))
                throw inkwell::Error("cannot write into '" + path_ + "': " + std::strerror(errno));
            staging_ = pattern;
            stagingSlot_ = inkwell::registerTemporaryDirectory(staging_);  // removed on SIGINT/SIGTERM/SIGHUP too
        }
        return staging_;
    }

    // Swaps the staged frames in (see above). `names` are the new frames, `stale` the old manifest's; none of
    // `keep` (the inputs and the stats: a stale frame's name may be one) is removed.
    void commit(const std::string& manifestPath, const std::vector<std::string>& names,
                const std::vector<std::string>& stale, const std::vector<std::string>& keep) {
        namespace fs = std::filesystem;
        if (::unlink(manifestPath.c_str()) != 0 && errno != ENOENT)
            throw inkwell::Error("cannot remove the old '" + manifestPath + "': " + std::strerror(errno));
        committed_ = true;  // from here the old capture is gone: its directories stay
        for (const std::string& name : names) {
            std::string from = (fs::path(staging_) / name).string(), to = (fs::path(path_) / name).string();
            if (::rename(from.c_str(), to.c_str()) != 0)
                throw inkwell::Error("cannot write '" + to + "': " + std::strerror(errno));
        }
        const std::set<std::string> fresh(names.begin(), names.end());
        for (const std::string& name : stale) {
            std::string path = (fs::path(path_) / name).string();
            bool kept = std::any_of(keep.begin(), keep.end(),
                                    [&](const std::string& k) { return !k.empty() && inkwell::sameFile(path, k); });
            if (!fresh.count(name) && !kept) ::unlink(path.c_str());  // best effort: no manifest names it now
        }
    }

private:
    void removeCreated() {
        std::error_code error;
        for (const auto& dir : created_) std::filesystem::remove(dir, error);  // deepest first; only if empty
    }
    std::string path_, staging_;
    int stagingSlot_ = -1;
    std::vector<std::filesystem::path> created_;
    bool committed_ = false;
};

// frame_0000.png ... : the only names a manifest's frames may have (a manifest names what a re-capture removes).
std::string frameName(uint32_t i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04u.png", i);
    return name;
}

bool isFrameName(const std::string& name) {
    if (name.size() != 14 || name.compare(0, 6, "frame_") != 0 || name.compare(10, 4, ".png") != 0) return false;
    return std::all_of(name.begin() + 6, name.begin() + 10, [](char c) { return c >= '0' && c <= '9'; });
}

// The frames the manifest in the directory lists (none when it is missing or not a manifest).
std::vector<std::string> manifestFrames(const std::string& manifestPath) {
    std::vector<std::string> names;
    try {
        std::string text = inkwell::readFileCapped(manifestPath, size_t(16) << 20, "too large");
        nlohmann::json m = nlohmann::json::parse(text);
        for (const auto& f : m.at("frames"))
            if (f.is_object() && f.contains("file") && f["file"].is_string() &&
                isFrameName(f["file"].get<std::string>()))
                names.push_back(f["file"].get<std::string>());
    } catch (const std::exception&) {
        names.clear();
    }
    return names;
}

int runCapture(Options& o, const CaptureOptions& c) {
    finishOptions(o);
    if (!std::isfinite(c.orbitDeg)) throw inkwell::Error("--orbit must be a finite number of degrees");
    CaptureOutput output(c.directory);
    namespace fs = std::filesystem;
    std::string manifestPath = (fs::path(c.directory) / "manifest.json").string();
    // After the directory: the stats may go into it. A directory that exists but cannot be written to is
    // refused here, as is an output that is an input.
    inkwell::checkOutputs({manifestPath, o.statsPath}, {o.model, o.preset});
    // The frames too, before any work: none may be an input (a frame that is a link to the model), or the
    // stats, or something other than a file or link in the way.
    std::vector<std::string> names;
    for (uint32_t i = 0; i < c.frames; ++i) {
        names.push_back(frameName(i));
        std::string frame = (fs::path(c.directory) / names.back()).string();
        for (const std::string& input : {o.model, o.preset})
            if (!input.empty() && inkwell::sameFile(frame, input))
                throw inkwell::Error("cannot write '" + frame +
                                     "': it is also an input of this command (inputs are never modified)");
        if (!o.statsPath.empty() && inkwell::sameFile(frame, o.statsPath))
            throw inkwell::Error("cannot write '" + o.statsPath + "': it is also frame " + std::to_string(i) +
                                 " of the capture (it is given as two outputs)");
        std::error_code error;
        fs::file_status st = fs::symlink_status(frame, error);
        if (fs::exists(st) && !fs::is_regular_file(st) && !fs::is_symlink(st))
            throw inkwell::Error(
                "cannot write '" + frame + "': " +
                (fs::is_directory(st) ? "Is a directory" : "not a regular file: only regular files are replaced"));
    }
    const std::vector<std::string> stale = manifestFrames(manifestPath);
    auto start = Clock::now();
    inkwell::Device device = openDevice(o, o.validation);
    device.checkImageSize(o.size[0], o.size[1], o.look.supersample);
    const inkwell::Model model = loadModel(o);
    const inkwell::Drawing drawing(device, model, o.drawing, reporter());
    const ViewReport view = resolveView(o, drawing, float(o.size[0]) / float(o.size[1]));
    const inkwell::Camera base = cameraFrom(o);
    ordered frames = ordered::array();
    {
        inkwell::Renderer renderer(drawing, o.size[0], o.size[1], o.look);
        int percent = -1;  // the progress reported
        for (uint32_t i = 0; i < c.frames; ++i) {
            inkwell::Camera camera = base;
            // From i, not accumulated frame to frame, and in double: the last of 10000 frames is as exact
            // as the first.
            camera.azimuthDeg = float(double(base.azimuthDeg) + double(c.orbitDeg) * i / c.frames);
            const inkwell::Image image = renderer.render(camera);  // the contour of this view traced first
            checkValidation(device);  // before writing: a frame drawn with validation errors is not kept
            std::string staged = (fs::path(output.staging()) / names[i]).string();
            try {
                image.writePng(staged);
            } catch (const inkwell::Error& e) {  // named as the user knows it, not by the staging directory
                std::string message = e.what();
                std::string frame = (fs::path(c.directory) / names[i]).string();
                if (size_t at = message.find(staged); at != std::string::npos)
                    message.replace(at, staged.size(), frame);
                throw inkwell::Error(message);
            }
            frames.push_back({{"file", names[i]}, {"camera", cameraJson(camera)}});
            if (const int now = int(100.0 * double(i + 1) / double(c.frames)); reporter().progress && now != percent) {
                percent = now;
                reporter().progress("capture", i + 1, c.frames);
            }
        }
        if (reporter().progress && percent >= 0) reporter().progress("capture", c.frames, c.frames);
    }
    checkValidation(device);
    const uint64_t points = drawing.pointCount();
    const json drawn = json::parse(drawing.statsJson());
    const size_t controlPoints = model.report().controlPoints;
    ordered manifest = {{"model", o.model},
                        {"frames", frames},
                        {"parameters", parametersJson(o, controlPoints, drawn["refine"]["passes"].get<uint32_t>(), c)},
                        {"device", device.name()},
                        {"driver", device.driver()},
                        {"points", points}};
    // Written last, with the stats, both or neither: a manifest says the capture is complete.
    inkwell::OutputBatch outputs;
    writeOrdered(manifestPath, manifest);
    double seconds = secondsSince(start);
    writeJson(o.statsPath, {{"control_points", controlPoints},
                            {"fit", json::parse(model.statsJson())},
                            {"refine", {{"seconds", drawn["refine"]["seconds"]}, {"points", points}}},
                            {"frames", c.frames},
                            {"view", viewJson(view)},
                            {"seconds", seconds},
                            {"device", device.name()},
                            {"driver", device.driver()}});
    // Everything is written: only renames (and the stale frames' removal) are left.
    output.commit(manifestPath, names, stale, {o.model, o.preset, o.statsPath});
    outputs.commit();
    std::printf("%s: %zu control points, %llu points, %u frames, %.2f s -> %s\n", o.model.c_str(), controlPoints,
                (unsigned long long)points, c.frames, seconds, manifestPath.c_str());
    return 0;
}

// readPng, but a missing file gets the system's reason as the model loaders give it (stb says "can't fopen").
inkwell::Image readImage(const std::string& path) {
    errno = 0;
    if (std::FILE* f = std::fopen(path.c_str(), "rb"))
        std::fclose(f);
    else
        throw inkwell::Error("cannot open '" + path + "': " + std::strerror(errno));
    return inkwell::Image::readPng(path);
}

std::string defaultDiffPath(const std::string& b) {
    std::filesystem::path p(b);
    return (p.parent_path() / (p.stem().string() + "-diff.png")).string();
}

// 0: within tolerance; 1: the images differ (or cannot be compared). Prints one line either way.
int runCompare(const CompareOptions& c) {
    std::string diffPath = c.diff.empty() ? defaultDiffPath(c.b) : c.diff;
    for (const std::string& input : {c.a, c.b})  // never over a reference: refused before the images are read
        if (inkwell::sameFile(diffPath, input))
            throw inkwell::Error("cannot write '" + diffPath +
                                 "': it is also an input of this command (inputs are never modified)");
    inkwell::Image a = readImage(c.a), b = readImage(c.b);
    if (a.width != b.width || a.height != b.height) {
        std::printf("images differ in size: '%s' is %ux%u, '%s' is %ux%u\n", c.a.c_str(), a.width, a.height,
                    c.b.c_str(), b.width, b.height);
        return 1;
    }
    const inkwell::ImageDifference result = inkwell::compareImages(a, b, c.threshold);
    if (result.sameSize && result.differingFraction <= c.maxFraction) {
        std::printf("%s\n", result.text.c_str());
        return 0;
    }
    inkwell::Image diff = inkwell::differenceImage(a, b, c.threshold);
    a = {};  // the inputs go before the diff is encoded: three images of 2^26 pixels at most at any time
    b = {};
    diff.writePng(diffPath);
    std::printf("%s: over %.3f%%, diff -> %s\n", result.text.c_str(), 100.0 * c.maxFraction, diffPath.c_str());
    return 1;
}

}  // namespace

void addCaptureCommands(CLI::App& cli, Options& o, Commands& commands) {
    auto capture = std::make_shared<CaptureOptions>();
    CLI::App* cap = cli.add_subcommand("capture", "Render frames along an orbit to PNGs, with a manifest");
    addModelOptions(cap, o);
    addRefineOptions(cap, o);
    addRenderOptions(cap, o);
    addDeviceOptions(cap, o);
    cap->add_option("--frames", capture->frames, "Frames to render")->required()->check(CLI::Range(1u, kMaxFrames));
    cap->add_option("--orbit", capture->orbitDeg, "Degrees of azimuth the frames span: frame i at orbit·i/N")
        ->capture_default_str();
    cap->add_option("-o,--output", capture->directory, "Output directory (created if missing)")->required();
    commands.emplace_back(cap, [&o, capture] { return runCapture(o, *capture); });

    auto compare = std::make_shared<CompareOptions>();
    CLI::App* cmp =
        cli.add_subcommand("compare", "Compare two PNGs: exit 0 if within tolerance, 1 if not (writing a diff image)");
    cmp->add_option("a", compare->a, "Reference PNG")->required();
    cmp->add_option("b", compare->b, "PNG to check")->required();
    cmp->add_option("--tolerance", compare->threshold,
                    "A pixel differs when a channel differs by more than this (0-255)")
        ->check(CLI::Range(0u, 255u))
        ->capture_default_str();
    cmp->add_option("--max-fraction", compare->maxFraction, "Largest fraction of pixels that may differ")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmp->add_option("--diff", compare->diff, "Diff image written on failure (default: B-diff.png beside B)");
    commands.emplace_back(cmp, [compare] { return runCompare(*compare); });
}

}  // namespace app
