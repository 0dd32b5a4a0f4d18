// Must not compile: cdb_scenes may not include registry/pipeline_kinds.h (tests/cli/layers_tests.sh).
#include "registry/pipeline_kinds.h"
