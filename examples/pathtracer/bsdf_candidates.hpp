// BSDF-sampled RIS candidates (--bsdf-candidates): at glossy pixels, light candidates drawn per
// pixel by power and directions drawn from the surface's BSDF, the emitter each direction hits
// taken as a light sample, all weighted by the balance heuristic
// (restir::resample_lights_and_bsdf). Lambertian pixels keep the source's own candidates.
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
