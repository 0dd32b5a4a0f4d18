// Must not compile: cdb_registry may not include the public API, a layer above it (tests/cli/layers_tests.sh).
#include "cdbench/cdbench.h"
