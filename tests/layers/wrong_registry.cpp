// Must not compile: cdb_registry may not include harness/results/results_file.h (tests/cli/layers_tests.sh).
#include "harness/results/results_file.h"
