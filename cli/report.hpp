#pragma once

// Text reports of the CLI: the composed graph and the per-topic statistics.

#include <cstdio>
#include <string>

#include "executors/launch.hpp"

namespace scancrew::cli {

// Components, topics with their type, publishers and subscribers; then the checks.
void print_graph(std::FILE* out, Launch& launch);
// The graph in Graphviz's DOT language (`scancrew graph --dot`): a digraph whose boxes are
// the components and ellipses the topics, an edge from each publisher to its topic and from
// the topic to each subscriber; a topic nobody publishes or nobody reads is dashed and red
// (the check's warnings).
void print_graph_dot(std::FILE* out, Launch& launch, const std::string& title);
// One line per topic: published, rate, taken, dropped, loan failures, latency. The rate is
// the messages published per second of the launch's clock over run_s seconds of it (sim
// time for a sim-clock launch, whatever its speed against the wall); latencies are wall time.
void print_topic_stats(std::FILE* out, const Graph& graph, double run_s);
// One progress line (overwritten in place on a terminal).
void print_progress(std::FILE* out, const Graph& graph, double elapsed_s, double duration_s,
                    bool final);

}  // namespace scancrew::cli
