// ExactOptions: the settings that decide what the exact method costs and where it gives way, the
// same for every command (query, render, precompute, view, screenshot, bench) and the viewer, with
// one set of defaults. None of them changes an exact answer: the build budget moves work from the
// precompute to the queries (a partial tree answers the same), the tree threshold chooses between
// a tree and the tree-less evaluation (the same answer), and the work limit is the one place
// where a point may be sampled instead (counted and reported, 0 = never), after the light-edge
// path's own limit.
#pragma once

#include <cstdint>

#include "engine/precompute/visibility_store.h"
#include "engine/render/renderer.h"

namespace penumbra {

struct ExactOptions {
    // History-tree build budget in linear programs (vis::BuildOptions::maxLpSolves; 0 = none).
    uint64_t maxLpSolves = vis::BuildOptions{}.maxLpSolves;
    // A pair the image samples fewer times gets no tree (RenderSettings::minTreeSamples).
    uint64_t minTreeSamples = RenderSettings{}.minTreeSamples;
    // A pair whose shaft holds this many faces, a quarter in face groups, gets no tree
    // (RenderSettings::groupedShaftMin; 0 = build it).
    uint32_t groupedShaftMin = RenderSettings{}.groupedShaftMin;
    // Plane tests one point's query may make before it is sampled
    // (RenderSettings::exactWorkLimit; 0 = every point exact).
    uint64_t exactWorkLimit = RenderSettings{}.exactWorkLimit;
    // Plane tests of the light-edge path tried on such a point before it is sampled
    // (RenderSettings::lightEdgeWorkLimit; 0 = sampled at once).
    uint64_t lightEdgeWorkLimit = RenderSettings{}.lightEdgeWorkLimit;
    // Occluders from which a point's query uses their boundary chain
    // (RenderSettings::chainMinOccluders; 0 = never).
    uint32_t chainMinOccluders = RenderSettings{}.chainMinOccluders;
    // Levels of query-driven refinement below a receiver patch (RenderSettings::refineLevels;
    // 0 = never).
    int refineLevels = RenderSettings{}.refineLevels;

    void applyTo(RenderSettings& settings) const {
        settings.minTreeSamples = minTreeSamples;
        settings.groupedShaftMin = groupedShaftMin;
        settings.exactWorkLimit = exactWorkLimit;
        settings.lightEdgeWorkLimit = lightEdgeWorkLimit;
        settings.chainMinOccluders = chainMinOccluders;
        settings.refineLevels = refineLevels;
    }
    void applyTo(VisibilityStore::Options& options) const {
        options.build.maxLpSolves = maxLpSolves;
    }
};

}  // namespace penumbra
