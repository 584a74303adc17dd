// GDP_CLONES: a function compiled for x86-64-v3 (AVX2, FMA) and for the baseline, the loader picking one.
#pragma once

#define GDP_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
