#pragma once

// Text reports of the CLI: the composed graph and the per-topic statistics.

#include <cstdio>

#include "executors/launch.hpp"

namespace scancrew::cli {

// Components, topics with their type, publishers and subscribers; then the checks.
void print_graph(std::FILE* out, Launch& launch);
// One line per topic: published, rate, taken, dropped, loan failures, latency.
void print_topic_stats(std::FILE* out, const Graph& graph);
// One progress line (overwritten in place on a terminal).
void print_progress(std::FILE* out, const Graph& graph, double elapsed_s, double duration_s,
                    bool final);

}  // namespace scancrew::cli
