#pragma once
// The start of every benchmark's main(): after benchmark::Initialize, the run's conditions
// (rpBenchmarkConditions.h: date, commit, build type, CPU, threads, load, screen, GL) are recorded,
// printed, and put in Google Benchmark's context, so its console output and --benchmark_out JSON
// name them; rp::bench::FinishConditions(directory, program) before benchmark::Shutdown() adds
// the load after the run and the steal time, and writes <program>-conditions.json beside the figures.
#include <benchmark/benchmark.h>

#include "rpBenchmarkConditions.h"

namespace rp::bench {

inline void AddConditionsToContext() {
  StartConditions();
  for (const auto& [name, value] : Conditions::Process().Fields()) benchmark::AddCustomContext(name, value);
}

}  // namespace rp::bench
