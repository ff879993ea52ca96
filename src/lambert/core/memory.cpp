#include "lambert/core/memory.h"

#include <cstdio>
#include <fstream>

namespace lambert {

double availableMemoryBytes() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  double kib = 0;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

double memoryBudgetBytes(double limitBytes) { return limitBytes > 0 ? limitBytes : availableMemoryBytes(); }

std::string formatBytes(double bytes) {
  const char* units[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB"};
  int unit = 0;
  while (bytes >= 1024 && unit < 5) bytes /= 1024, ++unit;
  char text[64];
  std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", bytes, units[unit]);
  return text;
}

std::string memoryExceeded(const std::string& what, double estimateBytes, double limitBytes) {
  return what + " needs " + formatBytes(estimateBytes) + ", more than the " + formatBytes(memoryBudgetBytes(limitBytes)) + " of memory " +
         (limitBytes > 0 ? "--memory-limit allows" : "available (MemAvailable)");
}

}  // namespace lambert
