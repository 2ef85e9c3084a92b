// The public surface of the hrbench engine: one include for the CLI, tests and benchmarks.
#pragma once

#include "counters.h"
#include "culling.h"
#include "element_tree.h"
#include "oracle.h"
#include "refine.h"
#include "run_report.h"
#include "scene.h"
#include "scene_io.h"
#include "util/args.h"
#include "util/error.h"
