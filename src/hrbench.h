// The public surface of the hrbench engine: one include for the CLI, tests and benchmarks.
#pragma once

#include "counters.h"
#include "culling.h"
#include "element_tree.h"
#include "mesh_io.h"
#include "oracle.h"
#include "polygon.h"
#include "polygon_forest.h"
#include "refine.h"
#include "run_report.h"
#include "scene.h"
#include "scene_io.h"
#include "translation_count.h"
#include "util/args.h"
#include "util/error.h"
#include "visibility.h"
