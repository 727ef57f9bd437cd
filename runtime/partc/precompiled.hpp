// partc/precompiled.hpp: the runtime headers that most generated models
// include, for partc_add_model to precompile once per build (CMake's
// target_precompile_headers; cmake/PartcAddModel.cmake) and every model to
// reuse: parsing them is over half of a model's compile (md.part's C++ at
// -O2: 2.0-2.2 s without, 1.2 s with). A model compiled without it includes
// the same headers itself, so the code and its results are the same.
#pragma once

#include <partc/domain.hpp>
#include <partc/driver.hpp>
#include <partc/errors.hpp>
#include <partc/finite.hpp>
#include <partc/io/csv.hpp>
#include <partc/math.hpp>
#include <partc/model_support.hpp>
#include <partc/parallel.hpp>
#include <partc/particle_set.hpp>
#include <partc/rng.hpp>
#include <partc/search/neighbour_search.hpp>
#include <partc/search/verlet_list.hpp>
#include <partc/vec.hpp>
