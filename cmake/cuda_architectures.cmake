# Which GPUs the CUDA code is compiled for, decided before enable_language(CUDA):
#  - -DCMAKE_CUDA_ARCHITECTURES=... (or the CUDAARCHS environment variable) wins;
#  - else, where nvidia-smi lists a GPU, `native`: only the GPUs of this machine (fastest
#    build, machine code for the card that runs it);
#  - else (no GPU here: a laptop, a cluster's login node) `75-virtual;90`: Hopper machine
#    code plus PTX for Turing (compute_75) and Hopper (compute_90). Every GPU from Turing on
#    runs it: Hopper from its machine code, Blackwell from the compute_90 PTX and Turing to
#    Ada from the compute_75 PTX, both compiled by the driver when the program first starts
#    on that card and cached by it (~/.nv/ComputeCache) for later runs. Two device passes
#    instead of the five of a Turing-to-Hopper machine-code list: docs/usage.md "Building"
#    has the measured build times that chose it.
# Code compiled for an architecture before Hopper has no wait for programmatic dependent
# launch; the CUDA executor turns that launch off where the loaded code lacks it
# (exec/cuda_exec.cu), so the PTX path stays correct on Hopper and later cards too.
if(DEFINED CMAKE_CUDA_ARCHITECTURES OR DEFINED ENV{CUDAARCHS})
  return()
endif()
execute_process(COMMAND nvidia-smi --list-gpus OUTPUT_VARIABLE cdb_gpus RESULT_VARIABLE cdb_smi_rc ERROR_QUIET)
if(cdb_smi_rc EQUAL 0 AND cdb_gpus MATCHES "GPU 0")
  set(CMAKE_CUDA_ARCHITECTURES native CACHE STRING "GPU architectures to compile for (native: this machine's)")
  return()
endif()
set(CMAKE_CUDA_ARCHITECTURES "75-virtual;90" CACHE STRING
    "GPU architectures to compile for (no GPU visible: PTX for Turing on, machine code for Hopper)")
