// A Vulkan context with validation and synchronization validation on; every GPU test ends by checking
// that the debug messenger counted no error.
#pragma once

#include "context.h"
#include "refine.h"

#include <doctest/doctest.h>

struct GpuFixture {
    ink::Context ctx;
    GpuFixture() {
        ink::ContextOptions options;
        options.validation = true;
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
    ink::Context& ctx;
    ink::GpuRefinement r;
    Refinement(ink::Context& context, const ink::Hrbf& hrbf, const ink::RefineOptions& options) : ctx(context) {
        try {
            ink::createRefinement(ctx, r, hrbf, options);
            ink::runRefinement(ctx, r);
        } catch (...) {
            ink::destroyRefinement(ctx, r);
            throw;
        }
    }
    ~Refinement() { ink::destroyRefinement(ctx, r); }
    Refinement(const Refinement&) = delete;
    Refinement& operator=(const Refinement&) = delete;
};
