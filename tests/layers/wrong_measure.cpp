// Must not compile: cdb_measure may not include app/, the command line above it (tests/cli/layers_tests.sh).
#include "run_loop.h"
