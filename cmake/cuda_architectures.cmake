# Which GPUs the CUDA code is compiled for, decided before enable_language(CUDA):
#  - -DCMAKE_CUDA_ARCHITECTURES=... (or the CUDAARCHS environment variable) wins;
#  - else, where nvidia-smi lists a GPU, `native`: only the GPUs of this machine (fastest
#    build, a binary for this machine);
#  - else every architecture from Volta to Hopper that this nvcc can compile for:
#    70 (V100), 75 (T4, RTX 20xx), 80 (A100), 86 (RTX 30xx, A10/A40), 89 (L4, L40, RTX 40xx),
#    90 (H100/H200). CUDA 13 dropped sm_70, so with it the list starts at 75.
# Blackwell (100, 120) is left out: it runs the compute_90 PTX embedded for the last entry,
# compiled by the driver at first launch.
if(DEFINED CMAKE_CUDA_ARCHITECTURES OR DEFINED ENV{CUDAARCHS})
  return()
endif()
execute_process(COMMAND nvidia-smi --list-gpus OUTPUT_VARIABLE cdb_gpus RESULT_VARIABLE cdb_smi_rc ERROR_QUIET)
if(cdb_smi_rc EQUAL 0 AND cdb_gpus MATCHES "GPU 0")
  set(CMAKE_CUDA_ARCHITECTURES native CACHE STRING "GPU architectures to compile for (native: this machine's)")
  return()
endif()
execute_process(COMMAND ${CMAKE_CUDA_COMPILER} --list-gpu-arch OUTPUT_VARIABLE cdb_known RESULT_VARIABLE cdb_list_rc
                ERROR_QUIET)
set(cdb_archs "")
foreach(arch 70 75 80 86 89 90)
  # An nvcc too old for --list-gpu-arch gets the whole list.
  if(NOT cdb_list_rc EQUAL 0 OR cdb_known MATCHES "compute_${arch}")
    list(APPEND cdb_archs ${arch})
  endif()
endforeach()
# The last one as real code and PTX, so newer GPUs can run it too.
list(POP_BACK cdb_archs cdb_newest)
list(TRANSFORM cdb_archs APPEND "-real")
list(APPEND cdb_archs ${cdb_newest})
set(CMAKE_CUDA_ARCHITECTURES "${cdb_archs}" CACHE STRING "GPU architectures to compile for")
