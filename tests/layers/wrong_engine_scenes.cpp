// Must not compile: cdb_engine may not include scenes/load/scene.h (tests/cli/layers_tests.sh).
#include "scenes/load/scene.h"
