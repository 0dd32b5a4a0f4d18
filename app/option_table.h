#pragma once
// Every option of `run`, one row each (option_table.cpp): the pipelines it acts on, what
// `compare` makes of it, whether a sweep may put it on an axis. The commands, compare, the
// sweep and the results file (params_json's identity_options, which scripts/cdb_results.py
// reads) all derive from it; a test (tests/test_option_table.cpp) fails when an option bound
// on `run` has no row or a row names no bound option. The help texts live with the bindings,
// in options.cpp and run_command.cpp.
#include <span>
#include <string>
#include <vector>

namespace cdb {

// The pipelines an option acts on; option_scope.h says what each covers.
enum class OptionScope {
  every,        // every pipeline: the scene, the boxes, the measurement
  hierarchy,    // pipelines that refit or rebuild a BVH: the front pipelines and bvh
  fronts,       // the front pipelines (a, b, c and their orderings)
  restructure,  // the front pipelines that restructure (c)
};

// What `compare` makes of an option recorded in a results file's params_json.
enum class ComparedAs {
  // Runs that differ in it are different experiments: it changes the pair set or how time
  // is measured. Never paired (unless --allow-mismatch, flagged).
  identity,
  // What a comparison is about (tuning knobs, plans): runs of one identity pair across it;
  // among several runs of one identity, the one of the same settings pairs.
  setting,
  // Neither: where the output went, how it was printed, how many passes were averaged
  // (repeats combine), and what the identity already holds in resolved form (the scene,
  // pipeline, device, frames, warm-up).
  not_compared,
};

// Whether a sweep file may give the option on an axis, or the sweep sets it per cell itself.
enum class InSweep { axis, per_cell };

struct OptionRow {
  const char* name;  // the long flag without "--", as params_json's options records it
  OptionScope scope;
  ComparedAs compared_as;
  InSweep in_sweep = InSweep::axis;
};

// Every row; the identity rows in the order compare lists their differences.
std::span<const OptionRow> option_table();

// The row of `name` (without "--"), nullptr for none (verify's own options, or an option a
// file recorded that this build no longer has).
const OptionRow* find_option_row(const std::string& name);

// The scope of an option by its flag ("--front-cycle"); every for options outside the table.
OptionScope option_scope(const std::string& flag);

// The identity options' names, in the table's order: what compare matches runs on beside
// the scene, pipeline, device, frames and warm-up, and what `run` records as params_json's
// identity_options.
std::vector<std::string> identity_options();

// Whether compare leaves a recorded option out of a run's configuration: a not-compared
// row. An option outside the table (of an older or newer build) is compared.
bool ignored_by_compare(const std::string& name);

// Whether the sweep sets `name` per cell, so a sweep file may not give it on an axis.
bool sweep_sets(const std::string& name);

}  // namespace cdb
