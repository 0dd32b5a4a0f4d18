// Must not compile: cdb_engine may not include baselines/grid/grid_pipeline.h (tests/cli/layers_tests.sh).
#include "baselines/grid/grid_pipeline.h"
