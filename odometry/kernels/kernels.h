#pragma once
// The narrow interface of odometry/kernels/ to the science files of odometry/: the kernel
// table and its buffers and sums (rgbd_kernels.h), the pooled float arrays the per-term
// buffers live in (pooled_floats.h), and the chunked loops whose results do not depend on
// the thread count (parallel_chunks.h). The lane types and kernel templates stay private.
#include "odometry/kernels/parallel_chunks.h"
#include "odometry/kernels/pooled_floats.h"
#include "odometry/kernels/rgbd_kernels.h"
