// cdbench command line: builds the commands' options and runs the one given. Each command
// lives in its own file (run_command, verify_command, scenes_command, sweep_command,
// compare_command, picture_command; report in results_table); the options they share in options.h. Nothing algorithmic lives here.
#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "cli_params.h"
#include "compare_command.h"
#include "cdbench/core/error.h"
#include "exit_codes.h"
#include "help_format.h"
#include "library_errors.h"
#include "options.h"
#include "picture_command.h"
#include "plan_table.h"
#include "results_table.h"
#include "run_command.h"
#include "scenes_command.h"
#include "sweep_command.h"
#include "verify_command.h"
#include "version_text.h"

using namespace cdb;

namespace {

// What a command prints on stdout is its result (report --csv/--json, compare --json, run --json,
// report --plan): a stdout the system refused (a full disk, /dev/full) fails the command,
// said on stderr, where it would otherwise end 0 with its output lost. Checked by the
// flush at the end, which also writes out what the buffer still held.
int check_stdout(int rc) {
  std::cout.flush();
  errno = 0;
  const bool flush_failed = std::fflush(stdout) != 0;
  const int error = errno;
  if (!flush_failed && !std::ferror(stdout) && !std::cout.bad()) return rc;
  // The reason is known only when this flush was refused, not an earlier one.
  std::fprintf(stderr, "cdbench: error: writing to standard output failed%s%s: what it printed is incomplete\n",
               flush_failed && error ? ": " : "", flush_failed && error ? std::strerror(error) : "");
  return rc == kExitOk ? kExitFailure : rc;
}

// Edits (insertions, deletions, substitutions) between two words.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// A first word that names no command: said as such, with the nearest command when one is
// close, rather than CLI11's "The following arguments were not expected".
void check_command(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return;
  const std::string given = argv[1];
  std::string nearest;
  size_t best = 3;  // at most two edits away
  for (const CLI::App* command : app.get_subcommands({})) {
    if (command->get_name() == given) return;
    const size_t d = edit_distance(given, command->get_name());
    if (d < best) best = d, nearest = command->get_name();
  }
  fail_usage("unknown command '" + given + "'" + (nearest.empty() ? "" : " (did you mean " + nearest + "?)") +
             "; the commands: run, verify, report, compare, sweep, scenes, picture (cdbench --help)");
}

int run_cli(int argc, char** argv) {
  // Every kernel loads when the CUDA context starts, not at its first launch: under CUDA's
  // default lazy loading the first frames that launch a kernel paid for loading it, inside
  // the timed frames (docs/experiments.md). An environment that sets CUDA_MODULE_LOADING
  // keeps its choice; sweep cells inherit this one.
  setenv("CUDA_MODULE_LOADING", "EAGER", 0);
  // A write past the file size limit (ulimit -f) fails with EFBIG and is reported like a
  // full disk, by every command that writes (run --out, scenes generate, verify
  // --write-pairs), instead of killing the process mid-write with its file cut off.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"cdbench: GPU broad-phase collision detection benchmark for deforming meshes"};
  // Set before the subcommands are added: each takes its parent's formatter.
  app.formatter(std::make_shared<WrappedHelp>(help_width()));
  app.require_subcommand(1);
  app.set_version_flag("--version", version_text());

  CommonOptions o;  // run, verify and picture
  RunOptions r;
  CLI::App* run = add_run_command(app, o, r);
  VerifyOptions v;
  CLI::App* verify = add_verify_command(app, o, v);
  ScenesOptions s;
  const ScenesCommand scenes = add_scenes_command(app, s);

  auto* report = app.add_subcommand("report", "summarize results files as a Markdown table (or CSV, or JSON)");
  std::vector<std::string> report_files;
  bool csv = false;
  report->add_option("files", report_files,
                     "results files written by run --out, or directories: every .h5 under them, and the sweep cells that left none")
      ->required();
  auto* report_csv = report->add_flag("--csv", csv, "CSV instead of Markdown");
  bool report_json = false;
  report
      ->add_flag("--json", report_json,
                 "JSON instead of Markdown: one object per file, the CSV's columns as keys, numbers at full precision")
      ->excludes(report_csv);
  bool plan = false;
  report
      ->add_flag("--plan", plan,
                 "print one pass's front plan as a plan file for run --front-cycle, instead of the table: the file "
                 "given is FILE.h5 (pass 0), FILE.h5:PIPELINE or FILE.h5:PIPELINE:PASS, or a plan file to check")
      ->excludes("--csv")
      ->excludes("--json");

  SweepOptions w;
  CLI::App* sweep = add_sweep_command(app, w);
  CompareOptions cmp;
  CLI::App* compare = add_compare_command(app, cmp);
  PictureOptions pic;
  CLI::App* picture = add_picture_command(app, o, pic);

  try {
    check_command(app, argc, argv);
  } catch (const UsageError& e) {
    std::fprintf(stderr, "cdbench: error: %s\n", e.what());
    return kExitUsage;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here with 0; every parse error is a usage error.
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  try {
    if (*run) o.given = given_flags(*run);
    if (*verify) o.given = given_flags(*verify);
    if (*run) return run_command(o, r, options_json(*run));
    if (*verify) return verify_command(o, v);
    if (*scenes.list) return scenes_list(s);
    if (*scenes.info) return scenes_info(s);
    if (*scenes.generate) return scenes_generate(s);
    if (*report && plan) return print_plan_file(report_files);
    if (*report)
      return print_results_table(report_files, report_json ? ReportFormat::json
                                               : csv       ? ReportFormat::csv
                                                           : ReportFormat::markdown);
    if (*sweep) return sweep_command(w, *run);
    if (*compare) return compare_command(cmp);
    if (*picture) return picture_command(o, pic);
  } catch (const UsageError& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "cdbench: error: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "cdbench: error: %s\n", error_text(e).c_str());
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

int main(int argc, char** argv) { return check_stdout(run_cli(argc, argv)); }
