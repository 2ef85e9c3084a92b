// Attaches the engine's counters to a benchmark row, named as CounterTable() names them,
// so that counts and times sit in the same JSON record.
#pragma once

#include <benchmark/benchmark.h>

#include "hrbench/record.h"

namespace hrbench {

// Every scalar counter of _counters_ as a user counter of the row (exact integers,
// identical on every iteration).
inline void AddRecordCounters(benchmark::State &state, const Counters &counters) {
    for (const CounterInfo &c : CounterTable())
        if (c.scalar)
            state.counters[c.name] = double(counters.*c.scalar);
}

}  // namespace hrbench
