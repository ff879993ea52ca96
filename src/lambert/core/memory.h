#pragma once
// How much memory a solve may take: what the machine has available now (Linux's MemAvailable),
// or a limit the user sets instead. Large allocations (the dense form-factor matrix, the
// hierarchical links, the adaptive active set's matrix and master-table pairs) are estimated
// against it first, so a solve that cannot fit stops at once with the figure instead of being
// killed hours later.
#include <string>

namespace lambert {

// MemAvailable from /proc/meminfo, in bytes; 0 where unknown (no check is made then).
double availableMemoryBytes();

// `limitBytes` when positive, else availableMemoryBytes().
double memoryBudgetBytes(double limitBytes);

// "11.0 GiB", "512 MiB": bytes for people.
std::string formatBytes(double bytes);

// A sentence for an estimate over the budget: "<what> needs <estimate>, more than the <budget>
// of memory <source>".
std::string memoryExceeded(const std::string& what, double estimateBytes, double limitBytes);

}  // namespace lambert
