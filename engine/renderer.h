// Draws refined points as ink dots with a graphics pipeline, straight from the refinement's device buffers
// (indirect draw, no readback). The offscreen target is what `render`, `capture` and the tests read back.
#pragma once

#include "camera.h"
#include "pipelines.h"
#include "refine.h"
#include "resources.h"

#include <glm/glm.hpp>
#include <vector>

namespace ink {

struct RenderStyle {
    glm::vec4 ink{0.0f, 0.0f, 0.0f, 1.0f};
    glm::vec4 paper{1.0f, 1.0f, 1.0f, 1.0f};
    glm::vec4 backInk{0.6f, 0.6f, 0.6f, 1.0f};
    float frontSize = 2.0f;       // dot diameter in output pixels
    float silhouetteSize = 3.0f;
    float backSize = 1.0f;
    float tau = 0.1f;             // τ of the silhouette test
    bool drawBack = false;
    glm::vec3 light{-0.4f, 0.8f, 0.6f};  // towards the light, model coordinates
    float toneGamma = 0.0f;       // 0: every front point is drawn
    uint32_t supersample = 2;     // render at this factor and filter down
};

// Matches `Style` in points.vert (std140).
struct StyleBlock {
    glm::vec4 color[3];
    glm::vec4 size;
    glm::vec4 light;
    glm::vec4 misc;
};
StyleBlock makeStyleBlock(const RenderStyle& style, float pointSizeMin, float pointSizeMax);

struct PointPipeline {
    DescriptorSet descriptors;
    Buffer style;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
};
PointPipeline createPointPipeline(Context& ctx, const Buffer& points, VkFormat colorFormat, VkFormat depthFormat);
void destroyPointPipeline(Context& ctx, PointPipeline& p);
// Inside dynamic rendering: binds, sets viewport/scissor and draws the points with the refinement's arguments.
void drawPoints(VkCommandBuffer cmd, const PointPipeline& p, const GpuRefinement& r, const Camera& camera,
                VkExtent2D extent);

struct OffscreenTarget {
    Image color, depth;
    Buffer readback;
};
OffscreenTarget createOffscreenTarget(Context& ctx, uint32_t width, uint32_t height);
void destroyOffscreenTarget(Context& ctx, OffscreenTarget& t);

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

struct RgbaImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> pixels;  // RGBA8, rows top to bottom
};

// Renders one frame of the refinement's points and returns it at width × height (supersampled inside).
class OffscreenRenderer {
public:
    OffscreenRenderer(Context& ctx, uint32_t width, uint32_t height, const RenderStyle& style,
                      const GpuRefinement& refinement);
    ~OffscreenRenderer();
    OffscreenRenderer(const OffscreenRenderer&) = delete;
    OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

    void setStyle(const RenderStyle& style);
    RgbaImage render(const Camera& camera);

private:
    Context& ctx_;
    const GpuRefinement& refinement_;
    RenderStyle style_;
    uint32_t width_, height_, factor_;
    OffscreenTarget target_;
    PointPipeline pipeline_;
};

// Box-filters an image whose sides are `factor` times larger.
RgbaImage downsample(const RgbaImage& image, uint32_t factor);

}  // namespace ink
