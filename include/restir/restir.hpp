/// @file restir.hpp
/// Umbrella header: everything in the library.
#pragma once

#include "restir/config.hpp"

#include "restir/concepts.hpp"
#include "restir/core/discrete_sample.hpp"
#include "restir/core/math.hpp"
#include "restir/core/reservoir.hpp"
#include "restir/core/rng.hpp"
#include "restir/light/attenuation.hpp"
#include "restir/light/light_sample.hpp"
#include "restir/light/light_sampler.hpp"
#include "restir/reuse/bias_correction.hpp"
#include "restir/reuse/boiling_filter.hpp"
#include "restir/reuse/image_view.hpp"
#include "restir/reuse/neighbor_offsets.hpp"
#include "restir/reuse/reuse_input.hpp"
#include "restir/reuse/similarity.hpp"
#include "restir/reuse/spatial.hpp"
#include "restir/reuse/spatiotemporal.hpp"
#include "restir/reuse/temporal.hpp"
#include "restir/reuse/visibility.hpp"
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/ris.hpp"
