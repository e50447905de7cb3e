// BSDF-sampled RIS candidates (--bsdf-candidates): at glossy pixels smoother than
// --bsdf-max-roughness, the source's own light candidates (light tiles:
// restir::resample_tiles_and_bsdf; the light BVH: restir::resample_lights_and_bsdf with the
// BVH's pmf) beside directions drawn from the surface's BSDF, the emitter each direction hits
// taken as a light sample, all weighted by the balance heuristic. Sources that cannot tell their
// density at a point a BSDF ray found (the grid's tiles, tiles whose points are drawn again from
// the surface) leave the light candidates to be drawn per pixel by power. Other pixels keep the
// source's own candidates.
#pragma once

#include "candidate_sources.hpp"
#include "embree_scene.hpp"

#include <memory>

namespace pt {

/// `source`, with BSDF candidates at glossy pixels when `settings.bsdf_candidates` > 0 (else
/// `source` itself). `ray_offset`: how far BSDF rays start off the surface.
std::unique_ptr<InitialCandidates> with_bsdf_candidates(std::unique_ptr<InitialCandidates> source,
                                                        const RenderSettings& settings,
                                                        const EmbreeScene& rays,
                                                        const LightSet& lights, float ray_offset);

} // namespace pt
