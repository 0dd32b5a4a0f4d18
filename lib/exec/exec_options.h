#pragma once
// Choices a run makes about how its executor launches work (flags of cdbench run).

namespace cdb {

struct ExecOptions {
  // --dependent-launch (CUDA, sm_90 and later): every kernel of the executor is launched
  // with programmatic stream serialization, so its blocks may be scheduled while the kernel
  // before it on the stream still runs; each kernel waits for its predecessor to complete
  // (griddepcontrol.wait) before touching memory, so results are those of serial launches.
  // What it saves is the launch latency between dependent kernels, which small scenes' frames
  // are made of. The host executor ignores it.
  bool dependent_launch = true;
};

}  // namespace cdb
