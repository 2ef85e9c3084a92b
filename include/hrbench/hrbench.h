// The public surface of the hrbench engine, what the package installs: one include for a
// project that uses it. The headers only the engine uses are beside its sources in src/.
#pragma once

#include "hrbench/check_links.h"
#include "hrbench/count.h"
#include "hrbench/forest.h"
#include "hrbench/geometry/polygon.h"
#include "hrbench/geometry/segment.h"
#include "hrbench/link_dump.h"
#include "hrbench/links_csv.h"
#include "hrbench/mesh_io.h"
#include "hrbench/oracles/registry.h"
#include "hrbench/record.h"
#include "hrbench/refine.h"
#include "hrbench/refine_options.h"
#include "hrbench/scene.h"
#include "hrbench/scene_io.h"
#include "hrbench/solve.h"
#include "hrbench/util/error.h"
