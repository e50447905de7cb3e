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
#include "restir/sampling/alias_table.hpp"
#include "restir/sampling/ris.hpp"
