#pragma once
// The one way lambert runs work on all cores: TBB's work-stealing parallel_for. Each chunk first
// checks for a cancel (core/cancel.h): a Cancelled thrown there stops the other chunks and leaves
// through the caller (TBB cancels the loop's task group and rethrows).
#include <cstddef>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "lambert/core/cancel.h"

namespace lambert {

// Calls body(i) for every i in [begin, end), spread over all cores. body must be safe to run
// concurrently for distinct i. grain is the smallest chunk a thread takes.
template <class Body>
void parallelFor(std::size_t begin, std::size_t end, Body&& body, std::size_t grain = 1) {
  if (begin >= end) return;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, grain),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      throwIfCancelled();
                      for (std::size_t i = range.begin(); i != range.end(); ++i) body(i);
                    });
}

}  // namespace lambert
