// What draws a Drawing (include/inkwell/inkwell.h): images, pages and plots, the Renderer (offscreen) and the
// FrameRecorder (the application's frames).
#include "api/impl.h"
#include "api/stats_json.h"
#include "inkwell/ranges.h"

#include "base/common.h"
#include "base/compare.h"
#include "base/image.h"
#include "draw/renderer.h"
#include "vector/vector.h"

#include <algorithm>
#include <utility>

namespace inkwell {

// ---- Rendering

namespace {

// A public Image's pixels, checked: its rgba holds width × height × 4 bytes.
ink::PixelsView pixels(const Image& image, const char* what) {
    if (image.rgba.size() != size_t(image.width) * image.height * 4)
        throw Error(std::string(what) + ": an Image's rgba must hold width × height × 4 bytes (" +
                    std::to_string(image.width) + " × " + std::to_string(image.height) + " × 4, not " +
                    std::to_string(image.rgba.size()) + ")");
    return {image.width, image.height, image.rgba.data()};
}

}  // namespace

void Image::writePng(const std::string& path) const {
    pixels(*this, "Image::writePng");
    if (width == 0 || height == 0) throw Error("cannot write '" + path + "': the image is empty");
    ink::writePng(path, width, height, rgba.data());
}

Image Image::readPng(const std::string& path) {
    ink::RgbaImage image = ink::readPng(path);
    return {image.width, image.height, std::move(image.pixels)};
}

ImageDifference compareImages(const Image& a, const Image& b, uint32_t threshold) {
    if (threshold > 255) throw Error("compareImages: the threshold must be in [0, 255]");
    const ink::CompareResult r =
        ink::compareImages(pixels(a, "compareImages"), pixels(b, "compareImages"), uint8_t(std::min(threshold, 255u)));
    return {r.maxAbsDiff, r.differingPixels, r.pixels, r.differingFraction, r.sameSize, ink::describe(r)};
}

Image differenceImage(const Image& a, const Image& b, uint32_t threshold) {
    if (threshold > 255) throw Error("differenceImage: the threshold must be in [0, 255]");
    ink::RgbaImage d =
        ink::diffImage(pixels(a, "differenceImage"), pixels(b, "differenceImage"), uint8_t(std::min(threshold, 255u)));
    return {d.width, d.height, std::move(d.pixels)};
}

Up parseUp(const std::string& name) { return Up(int(ink::parseUpAxis(name))); }
const char* upName(Up up) { return ink::upAxisName(ink::UpAxis(int(up))); }
const char* styleName(Style style) { return ink::drawStyleName(api::toDrawStyle(style)); }

std::array<float, 3> Camera::eye() const {
    const glm::vec3 e = api::toCamera(*this).eye();
    return {e.x, e.y, e.z};
}

void Camera::pan(double dx, double dy, uint32_t height) {
    const ink::Camera c = api::toCamera(*this);
    const glm::mat4 view = c.view();
    const glm::vec3 right(view[0][0], view[1][0], view[2][0]);
    const glm::vec3 up(view[0][1], view[1][1], view[2][1]);
    const float viewHeight = 2.0f * c.distance * std::tan(glm::radians(c.fovyDeg) * 0.5f);
    const float perPixel = viewHeight / float(std::max(1u, height));
    const glm::vec3 moved = c.target + (-float(dx) * right + float(dy) * up) * perPixel;
    target = {moved.x, moved.y, moved.z};
}

Page Page::named(const std::string& size) {
    glm::dvec2 mm = ink::parsePageSize(size);
    Page page;
    page.widthMm = mm.x;
    page.heightMm = mm.y;
    return page;
}

namespace {

ink::PageOptions toPage(const Page& p) {
    ink::PageOptions o;
    o.width = p.widthMm;
    o.height = p.heightMm;
    o.orientation = ink::Orientation(int(p.orientation));  // the same order
    o.margin = p.marginMm;
    o.penWidth = p.penWidthMm;
    o.dotStyle = p.dotStyle == DotStyle::Tick ? ink::DotStyle::Tick : ink::DotStyle::Circle;
    o.order = p.orderPaths;
    o.simplify = p.simplify;
    o.retrace = p.retrace;
    o.merge = p.merge;
    o.drawSpeed = p.drawSpeed;
    o.travelSpeed = p.travelSpeed;
    o.liftSeconds = p.liftSeconds;
    if (!(o.width >= 10 && o.height >= 10 && o.width <= 5000 && o.height <= 5000))
        throw Error("a page's sides must be 10 to 5000 mm");
    ranges::simplify.check(o.simplify, "simplify");
    ranges::retrace.check(o.retrace, "retrace");
    ranges::merge.check(o.merge, "merge");
    ranges::plotSpeed.check(o.drawSpeed, "drawSpeed");
    ranges::plotSpeed.check(o.travelSpeed, "travelSpeed");
    ranges::liftTime.check(o.liftSeconds, "liftSeconds");
    return o;
}

}  // namespace

struct Plot::Impl {
    ink::Plot plot;
};

void Plot::write(const std::string& path) const {
    if (!ink::isVectorPath(path)) throw Error("'" + path + "' is not an .svg or .pdf file");
    ink::writePlot(path, impl_->plot);
}

std::vector<PenLayer> Plot::layers() const {
    std::vector<PenLayer> layers;
    for (const ink::PlotLayer& l : impl_->plot.layers)
        layers.push_back({l.pen, l.name, l.paths.size(), l.travelBefore, l.travelAfter, l.penDown, l.lifts,
                          l.plotSeconds, l.pathsBefore});
    return layers;
}

std::string Plot::statsJson() const { return api::plotJson(impl_->plot).dump(); }

bool Plot::isVectorPath(const std::string& path) { return ink::isVectorPath(path); }

// Whether `style` (made from `look`) is restyled for the drawing's contour as it is now (`contours`): Drawing::refine
// may turn it on or off, and with it the dots' silhouette class (api::dotsTau).
static bool restyled(const Look& look, bool contours, ink::RenderStyle& style) {
    const float tau = api::dotsTau(look, contours);
    if (tau == style.tau) return false;
    style.tau = tau;
    return true;
}

// A renderer's descriptors name the drawing's sets. Drawing::refine replaces those (after waiting for the
// device), so a renderer made before it is made again, for the new sets, before it next draws
// (VUID-vkCmdDispatch-None-02699 otherwise: descriptors of destroyed buffers).
struct Renderer::Impl {
    Drawing::Impl& drawing;
    uint32_t width, height;
    Look look;  // the style's source: with the drawing's contour on or off, its τ changes (api::toStyle)
    ink::RenderStyle style;
    uint64_t generation;
    std::unique_ptr<ink::OffscreenRenderer> renderer;
    bool rendered = false;  // a frame since the renderer was made for the drawing's sets
    Impl(Drawing::Impl& d, uint32_t w, uint32_t h, const Look& l)
        : drawing(d),
          width(w),
          height(h),
          look(l),
          style(api::toStyle(l, d.scene.lines.contours)),
          generation(d.generation),
          renderer(make()) {}
    std::unique_ptr<ink::OffscreenRenderer> make() const {
        return std::make_unique<ink::OffscreenRenderer>(drawing.scene.ctx, width, height, style,
                                                        drawing.scene.pointers(), drawing.scene.strokes.get());
    }
    // The renderer for the drawing's current sets and lines.
    ink::OffscreenRenderer& current() {
        if (generation != drawing.generation) {
            renderer.reset();
            renderer = make();
            generation = drawing.generation;
            rendered = false;
        }
        if (restyled(look, drawing.scene.lines.contours, style)) renderer->setStyle(style);
        return *renderer;
    }
};

Renderer::Renderer(const Drawing& drawing, uint32_t width, uint32_t height, const Look& look) {
    ink::Scene& scene = drawing.impl_->scene;
    ink::checkOffscreenSize(scene.ctx, width, height, api::toStyle(look, scene.lines.contours).supersample);
    impl_ = std::make_unique<Impl>(*drawing.impl_, width, height, look);
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

void Renderer::setLook(const Look& look) {
    ink::RenderStyle style = api::toStyle(look, impl_->drawing.scene.lines.contours);
    if (style.supersample != impl_->style.supersample)
        throw Error("setLook cannot change supersample (" + std::to_string(impl_->style.supersample) + " to " +
                    std::to_string(style.supersample) + "): make a new Renderer");
    style.up = impl_->style.up;
    impl_->look = look;
    impl_->style = style;
    impl_->current().setStyle(impl_->style);
}

Image Renderer::render(const Camera& camera) {
    ink::OffscreenRenderer& renderer = impl_->current();
    if (impl_->style.up != ink::UpAxis(int(camera.up))) {  // the fixed light is given about the up axis
        impl_->style.up = ink::UpAxis(int(camera.up));
        renderer.setStyle(impl_->style);
    }
    impl_->drawing.traceFor(api::toCamera(camera));
    ink::RgbaImage image = renderer.render(api::toCamera(camera));
    impl_->rendered = true;
    return {image.width, image.height, std::move(image.pixels)};
}

uint32_t Renderer::dotsDrawn() const {
    ink::OffscreenRenderer& renderer = impl_->current();
    return impl_->rendered ? renderer.drawnDots() : 0;
}

std::vector<PenLayer> Renderer::writeVector(const std::string& path, const Page& page) const {
    if (!Plot::isVectorPath(path)) throw Error("'" + path + "' is not an .svg or .pdf file");
    const Plot laidOut = plot(page);
    laidOut.write(path);
    return laidOut.layers();
}

Plot Renderer::plot(const Page& page) const {
    ink::OffscreenRenderer& renderer = impl_->current();
    if (!impl_->rendered) throw Error("Renderer::plot: no frame of the drawing's points rendered yet");
    return Plot(
        std::make_shared<const Plot::Impl>(Plot::Impl{ink::layoutPlot(renderer.vectorDrawing(), toPage(page))}));
}

std::string Renderer::statsJson() const {
    ink::OffscreenRenderer& renderer = impl_->current();
    if (!impl_->rendered) throw Error("Renderer::statsJson: no frame of the drawing's points rendered yet");
    return api::pageJson(renderer, impl_->drawing.scene.pointers().size(), impl_->style, impl_->width, impl_->height)
        .dump();
}

// As Renderer::Impl: made again for the drawing's new sets after Drawing::refine, before the next record.
struct FrameRecorder::Impl {
    Drawing::Impl& drawing;
    VkFormat format;
    uint32_t frames;
    uint64_t generation;
    std::unique_ptr<ink::PointRenderer> renderer;
    Look look;  // the style's source (Renderer::Impl)
    ink::RenderStyle style;
    bool restyle = true;
    std::vector<bool> recorded;  // a slot's frame recorded since the renderer was made for the drawing's sets
    // FrameTarget::capture: a slot's copy of its drawing (host-visible), and the extent it holds.
    std::vector<ink::Buffer> captures;
    std::vector<VkExtent2D> captured;
    Impl(Drawing::Impl& d, VkFormat f, uint32_t n, const Look& l)
        : drawing(d),
          format(f),
          frames(n),
          generation(d.generation),
          renderer(make()),
          look(l),
          style(api::toStyle(l, d.scene.lines.contours)),
          recorded(n),
          captures(n),
          captured(n) {}
    ~Impl() {
        for (ink::Buffer& b : captures)
            if (b.buffer) ink::destroyBuffer(drawing.scene.ctx, b);
    }
    std::unique_ptr<ink::PointRenderer> make() const {
        return std::make_unique<ink::PointRenderer>(drawing.scene.ctx, drawing.scene.pointers(), format, frames,
                                                    drawing.scene.strokes.get());
    }
    ink::PointRenderer& current() {
        if (generation != drawing.generation) {
            vkDeviceWaitIdle(drawing.scene.ctx.device);  // frames submitted since refine() still read the old
            renderer.reset();
            renderer = make();
            generation = drawing.generation;
            restyle = true;
            recorded.assign(frames, false);
        }
        if (restyled(look, drawing.scene.lines.contours, style)) restyle = true;
        return *renderer;
    }
};

FrameRecorder::FrameRecorder(const Drawing& drawing, VkFormat colorFormat, uint32_t framesInFlight, const Look& look) {
    if (framesInFlight < 1 || framesInFlight > 16) throw Error("framesInFlight must be 1 to 16");
    impl_ = std::make_unique<Impl>(*drawing.impl_, colorFormat, framesInFlight, look);
}

FrameRecorder::~FrameRecorder() = default;
FrameRecorder::FrameRecorder(FrameRecorder&&) noexcept = default;
FrameRecorder& FrameRecorder::operator=(FrameRecorder&&) noexcept = default;

void FrameRecorder::setLook(const Look& look) {
    impl_->look = look;
    impl_->style = api::toStyle(look, impl_->drawing.scene.lines.contours);
    impl_->restyle = true;
}

void FrameRecorder::record(VkCommandBuffer cmd, const Camera& camera, const FrameTarget& target, uint32_t frame,
                           bool traceContours) {
    if (frame >= impl_->frames)
        throw Error("frame " + std::to_string(frame) + " is not one of the " + std::to_string(impl_->frames) +
                    " frames in flight");
    ink::PointRenderer& renderer = impl_->current();
    if (impl_->style.up != ink::UpAxis(int(camera.up))) {
        impl_->style.up = ink::UpAxis(int(camera.up));
        impl_->restyle = true;
    }
    if (impl_->restyle) {
        renderer.setStyle(cmd, impl_->style, 1.0f);
        impl_->restyle = false;
    }
    if (traceContours) impl_->drawing.traceFor(api::toCamera(camera));  // waits for the device when the eye moved
    // The slot's previous submission is done (the application waited for it): its capture buffer may go, kept
    // only while the slot's frames are captured.
    ink::Context& ctx = impl_->drawing.scene.ctx;
    ink::Buffer& b = impl_->captures[frame];
    const VkDeviceSize bytes = VkDeviceSize(target.extent.width) * target.extent.height * 4;
    if (b.buffer && (!target.capture || b.size != bytes)) ink::destroyBuffer(ctx, b);
    ink::Buffer* capture = nullptr;
    if (target.capture) {
        if (!b.buffer) b = ink::createBuffer(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, ink::MemoryUse::Readback);
        impl_->captured[frame] = target.extent;
        capture = &b;
    }
    renderer.recordFrame(cmd, api::toCamera(camera), target, frame, capture);
    impl_->recorded[frame] = true;
}

Image FrameRecorder::captured(uint32_t frame) const {
    if (frame >= impl_->frames || !impl_->captures[frame].buffer)
        throw Error("FrameRecorder::captured: frame " + std::to_string(frame) +
                    "'s last recording was not made with FrameTarget::capture");
    const ink::Buffer& b = impl_->captures[frame];
    Image image{impl_->captured[frame].width, impl_->captured[frame].height, {}};
    const uint8_t* mapped = static_cast<const uint8_t*>(b.mapped);
    image.rgba.assign(mapped, mapped + b.size);
    switch (impl_->format) {  // to RGBA
        case VK_FORMAT_R8G8B8A8_UNORM:
        case VK_FORMAT_R8G8B8A8_SRGB:
            break;
        case VK_FORMAT_B8G8R8A8_UNORM:
        case VK_FORMAT_B8G8R8A8_SRGB:
            for (size_t i = 0; i + 3 < image.rgba.size(); i += 4) std::swap(image.rgba[i], image.rgba[i + 2]);
            break;
        default:
            throw Error("a captured frame needs an 8-bit RGBA or BGRA colour format");
    }
    return image;
}

std::vector<PenLayer> FrameRecorder::writeVector(const std::string& path, uint32_t frame, const Page& page) const {
    if (frame >= impl_->frames)
        throw Error("frame " + std::to_string(frame) + " is not one of the " + std::to_string(impl_->frames) +
                    " frames in flight");
    if (!Plot::isVectorPath(path)) throw Error("'" + path + "' is not an .svg or .pdf file");
    const Plot laidOut = plot(frame, page);
    laidOut.write(path);
    return laidOut.layers();
}

Plot FrameRecorder::plot(uint32_t frame, const Page& page) const {
    if (frame >= impl_->frames)
        throw Error("frame " + std::to_string(frame) + " is not one of the " + std::to_string(impl_->frames) +
                    " frames in flight");
    ink::PointRenderer& renderer = impl_->current();
    if (!impl_->recorded[frame])
        throw Error("FrameRecorder::plot: frame " + std::to_string(frame) +
                    " has recorded no frame of the drawing's points yet");
    return Plot(
        std::make_shared<const Plot::Impl>(Plot::Impl{ink::layoutPlot(renderer.vectorDrawing(frame), toPage(page))}));
}

}  // namespace inkwell
