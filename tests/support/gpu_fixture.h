// A Vulkan context with validation and synchronization validation on; every GPU test ends by checking
// that the debug messenger counted no error.
#pragma once

#include "gpu/context.h"
#include "refine/refine.h"

#include <doctest/doctest.h>
#include <cstdio>

struct GpuFixture {
    ink::Context ctx;
    // float64 false: a device as one without shaderFloat64 (the feature is not enabled, so validation flags any
    // shader that uses double).
    explicit GpuFixture(bool float64 = true) {
        ink::ContextOptions options;
        options.validation = true;
        options.float64 = float64;
        options.validationMessage = [](bool error, const std::string& message) {
            if (error) std::fprintf(stderr, "validation error: %s\n", message.c_str());
        };
        ink::createContext(ctx, options);
    }
    ~GpuFixture() { ink::destroyContext(ctx); }
    void requireNoValidationErrors() {
        INFO("first validation message: " << ctx.firstValidationMessage);
        CHECK(ctx.validationErrors.load() == 0);
    }
};

// A refinement made and run on a device, destroyed with this object (also when a REQUIRE throws).
struct Refinement {
    ink::Refinement owner;
    ink::GpuRefinement& r;
    Refinement(ink::Context& ctx, const ink::Surface& hrbf, const ink::RefineOptions& options)
        : owner(ctx, hrbf, options), r(owner.gpu()) {
        ink::runRefinement(ctx, r);
    }
};
