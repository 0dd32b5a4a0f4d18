// Must not compile: cdb_baselines may not include scenes/generators/generators.h (tests/cli/layers_tests.sh).
#include "scenes/generators/generators.h"
