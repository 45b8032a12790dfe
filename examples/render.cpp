// Renders a model to a PNG through Inkwell's public API alone:  render MODEL OUT.png [AZIMUTH]
#include <inkwell/inkwell.h>

#include <cstdio>
#include <string>

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s MODEL OUT.png [AZIMUTH]\n", argv[0]);
        return 2;
    }
    try {
        inkwell::Reporter reporter;
        reporter.note = [](const std::string& line) { std::fprintf(stderr, "note: %s\n", line.c_str()); };

        inkwell::Model model = inkwell::Model::load(argv[1], {}, reporter);  // fit a mesh, or read a .hrbf
        inkwell::Device device;                                              // a GPU, else lavapipe
        inkwell::Drawing drawing(device, model, {}, reporter);               // blue-noise stipples

        inkwell::Look look;
        look.inkDensity = 1.2f;
        inkwell::Renderer renderer(drawing, 800, 800, look);
        inkwell::Camera camera;
        if (argc > 3) camera.azimuthDeg = std::stof(argv[3]);
        inkwell::Image image = renderer.render(camera);
        image.writePng(argv[2]);

        std::printf("%s: %zu control points, %zu stipples, %u drawn -> %s\n", argv[1], model.report().controlPoints,
                    drawing.points().size(), renderer.dotsDrawn(), argv[2]);
    } catch (const inkwell::Error& e) {
        std::fprintf(stderr, "render: %s\n", e.what());
        return 1;
    }
    return 0;
}
