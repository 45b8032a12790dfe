// A Vulkan context with validation and synchronization validation on; every GPU test ends by checking
// that the debug messenger counted no error.
#pragma once

#include "context.h"

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
