#pragma once
// Heap allocations of this process so far (operator new, every thread): the overhead
// benchmark reads it around each frame to show that the API allocates nothing once sizes
// settle. Counting needs the replaced operator new of allocation_count.cpp linked in.
#include <cstdint>

uint64_t heap_allocations();
