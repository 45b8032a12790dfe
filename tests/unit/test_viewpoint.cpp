// The first picture (engine/surface/viewpoint.h): the up axis found from the shape, the view by viewpoint entropy, the
// framing; on generated shapes whose answer is known.
#include "surface/viewpoint.h"

#include <doctest/doctest.h>

#include <cmath>
#include <string>

namespace {

// Samples spread evenly over the surface of a union of axis-aligned boxes, `spacing` apart, with outward
// normals.
struct Box {
    glm::vec3 lo, hi;
};
ink::ViewSamples boxes(const std::vector<Box>& list, float spacing = 0.01f) {
    ink::ViewSamples s;
    for (const Box& b : list)
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
                const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                for (float a = b.lo[u] + spacing / 2; a < b.hi[u]; a += spacing)
                    for (float c = b.lo[v] + spacing / 2; c < b.hi[v]; c += spacing) {
                        glm::vec3 p, n(0);
                        p[axis] = side ? b.hi[axis] : b.lo[axis];
                        p[u] = a;
                        p[v] = c;
                        n[axis] = side ? 1.0f : -1.0f;
                        // Not inside or on another box: the union's surface only.
                        bool covered = false;
                        for (const Box& o : list)
                            covered |= &o != &b && glm::all(glm::greaterThanEqual(p, o.lo - 1e-5f)) &&
                                       glm::all(glm::lessThanEqual(p, o.hi + 1e-5f));
                        if (covered) continue;
                        s.positions.push_back(p);
                        s.normals.push_back(n);
                    }
            }
    // Centred on the bounding box, as the normalized coordinates are.
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (const glm::vec3& p : s.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    for (glm::vec3& p : s.positions) p -= 0.5f * (lo + hi);
    return s;
}

// The samples turned so that their y axis points along `up` (upBasis: y-up frame to the model's).
ink::ViewSamples turned(ink::ViewSamples s, ink::UpAxis up) {
    const glm::mat3 r = ink::upBasis(up);
    for (glm::vec3& p : s.positions) p = r * p;
    for (glm::vec3& n : s.normals) n = r * n;
    return s;
}

// A spider: a flat, lopsided shape (a wide thin plate, a body on top of it), y-up.
std::vector<Box> spider() {
    return {{{-0.4f, 0.0f, -0.4f}, {0.4f, 0.03f, 0.4f}}, {{-0.12f, 0.03f, -0.15f}, {0.12f, 0.16f, 0.15f}}};
}
// A camel: thin from flank to flank (x), with legs below and a hump above: flat across x, mirrored there.
std::vector<Box> camel() {
    return {{{-0.06f, 0.3f, -0.4f}, {0.06f, 0.5f, 0.4f}},    // body
            {{-0.06f, 0.5f, -0.1f}, {0.06f, 0.62f, 0.1f}},   // hump
            {{-0.05f, 0.0f, -0.38f}, {0.05f, 0.3f, -0.3f}},  // legs
            {{-0.05f, 0.0f, 0.3f}, {0.05f, 0.3f, 0.38f}},    //
            {{-0.05f, 0.5f, 0.4f}, {0.05f, 0.75f, 0.48f}}};  // neck
}
// A figure: a body with a shelf (arms) reaching out in front of it, +z, at chest height; feet below.
std::vector<Box> figure() {
    return {{{-0.15f, 0.2f, -0.1f}, {0.15f, 0.8f, 0.1f}},  // body
            {{-0.2f, 0.5f, 0.1f}, {0.2f, 0.56f, 0.35f}},   // arms, in front
            {{-0.12f, 0.0f, -0.06f}, {-0.03f, 0.2f, 0.06f}},
            {{0.03f, 0.0f, -0.06f}, {0.12f, 0.2f, 0.06f}}};
}

// A standing figure (CGAL's man.off): a tall body thin from front to back (z), shoulders wide, two feet below whose
// soles face down, a head on top; y-up.
std::vector<Box> standing() {
    return {{{-0.16f, 0.3f, -0.05f}, {0.16f, 0.75f, 0.05f}},  // body
            {{-0.06f, 0.75f, -0.05f}, {0.06f, 0.9f, 0.05f}},  // head
            {{-0.12f, 0.0f, -0.04f}, {-0.02f, 0.3f, 0.08f}},  // legs, the feet reaching forward
            {{0.02f, 0.0f, -0.04f}, {0.12f, 0.3f, 0.08f}}};
}

}  // namespace

TEST_CASE("viewpoint: the up axis of flat shapes is their thinnest, of others y, whichever axis the file uses" *
          doctest::test_suite("unit")) {
    for (ink::UpAxis up : {ink::UpAxis::PosX, ink::UpAxis::PosY, ink::UpAxis::PosZ}) {
        CAPTURE(ink::upAxisName(up));
        const ink::UpChoice flat = ink::detectUpAxis(turned(boxes(spider()), up));
        CHECK(flat.up == up);
        CHECK(flat.reason == "flat: its thinnest axis");
    }
    // The camel is thinnest across x, but mirrored there while y is lopsided: y.
    const ink::UpChoice c = ink::detectUpAxis(boxes(camel()));
    CHECK(c.sigma[2] < 0.55f * c.sigma[1]);
    CHECK(c.up == ink::UpAxis::PosY);
    // An upright figure, y-up: y; stored z-up it is not flat: still y (--up z says otherwise).
    CHECK(ink::detectUpAxis(boxes(figure())).up == ink::UpAxis::PosY);
    const ink::UpChoice z = ink::detectUpAxis(turned(boxes(figure()), ink::UpAxis::PosZ));
    CHECK(z.up == ink::UpAxis::PosY);
    CHECK(z.reason == "not flat: y");
    // A standing figure, tall, thin from front to back (flat by its spreads), its feet a base at the bottom: its long
    // axis up, whichever axis the file uses; stored upside down it is not taken for standing.
    for (ink::UpAxis up : {ink::UpAxis::PosX, ink::UpAxis::PosY, ink::UpAxis::PosZ}) {
        CAPTURE(ink::upAxisName(up));
        const ink::UpChoice s = ink::detectUpAxis(turned(boxes(standing()), up));
        CHECK(s.up == up);
        CHECK(s.reason == "standing: its longest axis, a base at its low end");
    }
    CHECK(ink::detectUpAxis(turned(boxes(standing()), ink::UpAxis::NegZ)).reason !=
          "standing: its longest axis, a base at its low end");
    // A plank lying (long, narrow, thin, like faces at both ends): flat, its thinnest axis up.
    CHECK(ink::detectUpAxis(boxes({{{-0.5f, 0.0f, -0.08f}, {0.5f, 0.03f, 0.08f}}})).up == ink::UpAxis::PosY);
    // Too few samples: y.
    CHECK(ink::detectUpAxis({}).up == ink::UpAxis::PosY);
    // The file's convention: glTF is +y by its specification; the other formats have none.
    CHECK(ink::formatUpAxis("a/b/Model.GLB") == ink::UpAxis::PosY);
    CHECK(ink::formatUpAxis("model.gltf") == ink::UpAxis::PosY);
    CHECK(!ink::formatUpAxis("model.stl"));
    CHECK(!ink::formatUpAxis("dir.gltf/model"));
}

TEST_CASE("viewpoint: the chosen view is on the figure's front side, not along its arms, nor along the L's axis" *
          doctest::test_suite("unit")) {
    // The figure's arms reach out in front (+z). The view is a three-quarter view (20-60° off) of the side found
    // to be the front (the side that hides the most of itself; on this box figure the back, where the body hides
    // the arms' top), never straight along x where the arms vanish into the body.
    for (ink::UpAxis up : {ink::UpAxis::PosY, ink::UpAxis::PosZ}) {
        CAPTURE(ink::upAxisName(up));
        const ink::ViewSamples s = turned(boxes(figure()), up);
        const ink::ViewChoice v = ink::chooseView(s, up);
        // A front was found (the figure is lopsided front to back), and the view is on its side of the figure.
        REQUIRE(v.frontDeg >= 0);
        const float off = std::abs(std::remainder(v.azimuthDeg - v.frontDeg, 360.0f));
        CHECK(off >= ink::kThreeQuarterMinDeg);
        CHECK(off <= ink::kThreeQuarterMaxDeg);
        CHECK(std::abs(std::abs(std::remainder(v.azimuthDeg, 360.0f)) - 90.0f) > 10.0f);
        // Deterministic.
        const ink::ViewChoice again = ink::chooseView(s, up);
        CHECK(again.azimuthDeg == v.azimuthDeg);
        CHECK(again.elevationDeg == v.elevationDeg);
    }
    // An L extruded along z: seen along z it is an L, along x a rectangle (the foot hides behind the upright).
    // The views along x score lower than the chosen one, which is not along x.
    const ink::ViewSamples l =
        boxes({{{0.0f, 0.0f, 0.0f}, {0.15f, 0.8f, 0.3f}}, {{0.15f, 0.0f, 0.0f}, {0.6f, 0.15f, 0.3f}}});
    const ink::ViewChoice v = ink::chooseView(l, ink::UpAxis::PosY);
    CAPTURE(v.azimuthDeg);
    CAPTURE(v.elevationDeg);
    const float az = std::abs(std::remainder(v.azimuthDeg, 180.0f));
    CHECK(az > 10.0f);
    CHECK(az < 80.0f);
    for (float side : {90.0f, 270.0f}) {
        const float a = glm::radians(side), e = glm::radians(v.elevationDeg);
        const ink::ViewScore along =
            ink::scoreView(l, glm::vec3(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a)));
        CHECK(along.entropy < v.score);
    }
    CHECK(v.elevationDeg >= 15.0f);
    CHECK(v.elevationDeg <= 30.0f);
}

TEST_CASE("viewpoint: a sphere with detail on one side is seen from that side, at three-quarters" *
          doctest::test_suite("unit")) {
    // An even sphere hides nothing of itself from any side; a rough cap (ripples in its normals, as a face or a
    // paw has) around `face` tells its front. Without the cap no front is found.
    const auto sphere = [](const glm::vec3& face, float ripples) {
        ink::ViewSamples s;
        const int n = 6000;
        for (int i = 0; i < n; ++i) {  // a Fibonacci sphere: even spacing
            const float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(n), r = std::sqrt(1.0f - y * y);
            const float a = 2.39996323f * float(i);
            const glm::vec3 p(r * std::cos(a), y, r * std::sin(a));
            glm::vec3 normal = p;
            if (glm::dot(p, face) > 0.7f)
                normal =
                    glm::normalize(p + ripples * glm::vec3(std::sin(40 * p.y), std::sin(40 * p.z), std::sin(40 * p.x)));
            s.positions.push_back(0.4f * p);
            s.normals.push_back(normal);
        }
        return s;
    };
    CHECK(ink::chooseView(sphere({1, 0, 0}, 0.0f), ink::UpAxis::PosY).frontDeg == -1.0f);
    for (float faceDeg : {90.0f, 200.0f}) {
        CAPTURE(faceDeg);
        const glm::vec3 face(std::sin(glm::radians(faceDeg)), 0, std::cos(glm::radians(faceDeg)));
        const ink::ViewChoice v = ink::chooseView(sphere(face, 0.6f), ink::UpAxis::PosY);
        CAPTURE(v.azimuthDeg);
        REQUIRE(v.frontDeg >= 0);
        CHECK(std::abs(std::remainder(v.frontDeg - faceDeg, 360.0f)) < 15.0f);
        const float off = std::abs(std::remainder(v.azimuthDeg - v.frontDeg, 360.0f));
        CHECK(off >= ink::kThreeQuarterMinDeg);
        CHECK(off <= ink::kThreeQuarterMaxDeg);
    }
    // The detail itself: 0 on the even part, larger on the cap.
    const ink::ViewSamples s = sphere({1, 0, 0}, 0.6f);
    const std::vector<float> d = ink::sampleDetail(s);
    REQUIRE(d.size() == s.positions.size());
    double even = 0, cap = 0;
    size_t nEven = 0, nCap = 0;
    for (size_t i = 0; i < d.size(); ++i)
        if (s.positions[i].x > 0.4f * 0.8f)
            cap += d[i], ++nCap;
        else if (s.positions[i].x < 0)
            even += d[i], ++nEven;
    CHECK(even / double(nEven) < 0.01);
    CHECK(cap / double(nCap) > 10 * even / double(nEven));
}

TEST_CASE("viewpoint: a one-sided scan is seen from the side it was scanned from, not into its open back" *
          doctest::test_suite("unit")) {
    // A scan from +z keeps only the surface that faced the scanner. From behind, an open surface shows its
    // back, which hides the few front-facing samples behind it: that is not the shape hiding itself (a front),
    // and such views must not be chosen. CGAL's hippo1.ply was drawn from its open back this way.
    const auto scanned = [](const ink::ViewSamples& all) {
        ink::ViewSamples s;
        for (size_t i = 0; i < all.positions.size(); ++i)
            if (all.normals[i].z > -0.3f) s.positions.push_back(all.positions[i]), s.normals.push_back(all.normals[i]);
        return s;
    };
    ink::ViewSamples ball;  // a Fibonacci sphere
    for (int i = 0, n = 6000; i < n; ++i) {
        const float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(n), r = std::sqrt(1.0f - y * y),
                    a = 2.39996323f * float(i);
        const glm::vec3 p(r * std::cos(a), y, r * std::sin(a));
        ball.positions.push_back(0.4f * p);
        ball.normals.push_back(p);
    }
    for (const auto& entry :
         {std::pair{std::string("figure"), scanned(boxes(figure()))}, std::pair{std::string("ball"), scanned(ball)}}) {
        const std::string& name = entry.first;  // CAPTURE's lambda cannot capture a structured binding before clang 16
        const ink::ViewSamples& samples = entry.second;
        CAPTURE(name);
        const ink::ViewChoice v = ink::chooseView(samples, ink::UpAxis::PosY);
        CAPTURE(v.azimuthDeg);
        CAPTURE(v.frontDeg);
        CHECK(std::abs(std::remainder(v.azimuthDeg, 360.0f)) < 90.0f);
        const float az = glm::radians(v.azimuthDeg), el = glm::radians(v.elevationDeg);
        const glm::vec3 eye(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
        CHECK(ink::scoreView(samples, eye).facing > 0.9f);
        // From straight behind, most of what shows is the back.
        CHECK(ink::scoreView(samples, glm::vec3(0, 0, -1)).facing < 0.5f);
    }
    // A closed surface faces the eye from every side.
    for (float azDeg : {30.0f, 120.0f, 210.0f, 300.0f}) {
        const glm::vec3 eye(std::sin(glm::radians(azDeg)), 0, std::cos(glm::radians(azDeg)));
        CHECK(ink::scoreView(boxes(figure()), eye).facing > 0.9f);
    }
}

TEST_CASE("viewpoint: framing puts the projected extent at 85% of the frame, centred" * doctest::test_suite("unit")) {
    for (float aspect : {1.0f, 1.5f, 0.6f}) {
        ink::Camera c;
        c.azimuthDeg = 40;
        c.elevationDeg = 25;
        const ink::ViewSamples s = boxes(camel());
        ink::frameSamples(c, s, aspect);
        const glm::mat4 m = c.projection(aspect) * c.view();
        glm::vec2 lo(1e9f), hi(-1e9f);
        for (const glm::vec3& p : s.positions) {
            const glm::vec4 q = m * glm::vec4(p, 1.0f);
            lo = glm::min(lo, glm::vec2(q) / q.w);
            hi = glm::max(hi, glm::vec2(q) / q.w);
        }
        CAPTURE(aspect);
        CHECK(std::max(hi.x - lo.x, hi.y - lo.y) / 2 == doctest::Approx(0.85).epsilon(0.01));
        CHECK(std::abs(hi.x + lo.x) < 0.01f);
        CHECK(std::abs(hi.y + lo.y) < 0.01f);
    }
}

TEST_CASE("viewpoint: a sheet drawn two-sided is seen face-on, from either side its normals face" *
          doctest::test_suite("unit")) {
    // A slightly rippled disk (a map, a terrain) tilted 45° about x, its normals facing down and towards -z (a
    // scan's estimated normals have either sign). Drawn one-sided only grazing views from above see its front;
    // two-sided, the view that sees most of it: face-on from above, within the candidates' 15° steps.
    ink::ViewSamples sheet;
    const glm::vec3 normal = glm::normalize(glm::vec3(0.0f, -1.0f, -1.0f));
    const glm::vec3 u(1.0f, 0.0f, 0.0f), w = glm::cross(normal, u);
    for (int i = 0; i < 6000; ++i) {  // a Fibonacci disk: even spacing
        const float r = 0.5f * std::sqrt((float(i) + 0.5f) / 6000.0f), a = 2.39996323f * float(i);
        const float bump = 0.004f * std::sin(30.0f * r * std::cos(a)) * std::sin(30.0f * r * std::sin(a));
        sheet.positions.push_back(r * std::cos(a) * u + r * std::sin(a) * w + bump * normal);
        sheet.normals.push_back(normal);
    }
    const auto seen = [&](const ink::ViewChoice& v) {  // |n·v| of the chosen view
        const float a = glm::radians(v.azimuthDeg), e = glm::radians(v.elevationDeg);
        return std::abs(glm::dot(normal, glm::vec3(std::cos(e) * std::sin(a), std::sin(e), std::cos(e) * std::cos(a))));
    };
    const ink::ViewChoice one = ink::chooseView(sheet, ink::UpAxis::PosY);
    CAPTURE(one.azimuthDeg);
    CHECK(seen(one) < 0.5f);  // 60° or more off face-on: along it
    sheet.twoSided = true;
    const ink::ViewChoice two = ink::chooseView(sheet, ink::UpAxis::PosY);
    CAPTURE(two.azimuthDeg);
    CAPTURE(two.elevationDeg);
    CHECK(seen(two) > 0.95f);  // face-on, its back: azimuth 0°, 30° above, 15° off its normal
    CHECK(two.frontDeg == -1.0f);
}
