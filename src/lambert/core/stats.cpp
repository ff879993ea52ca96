#include "lambert/core/stats.h"

#include <algorithm>
#include <cstdio>

namespace lambert {

void Stats::add(std::string key, std::string label, Value value, std::string unit) {
  entries_.push_back({std::move(key), std::move(label), std::move(value), std::move(unit)});
}

void Stats::append(const Stats& other) { entries_.insert(entries_.end(), other.entries_.begin(), other.entries_.end()); }

const Stats::Entry* Stats::find(const std::string& key) const {
  for (const Entry& e : entries_)
    if (e.key == key) return &e;
  return nullptr;
}

namespace {

std::string format(const Stats::Value& value) {
  char buffer[64];
  if (const auto* i = std::get_if<std::int64_t>(&value)) {
    std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(*i));
    return buffer;
  }
  if (const auto* d = std::get_if<double>(&value)) {
    double magnitude = *d < 0 ? -*d : *d;
    if (magnitude != 0 && (magnitude < 1e-3 || magnitude >= 1e7))
      std::snprintf(buffer, sizeof buffer, "%.3e", *d);
    else
      std::snprintf(buffer, sizeof buffer, "%.4g", *d);
    return buffer;
  }
  return std::get<std::string>(value);
}

}  // namespace

std::string Stats::table() const {
  std::size_t labelWidth = 0;
  for (const Entry& e : entries_) labelWidth = std::max(labelWidth, e.label.size());
  std::string out;
  for (const Entry& e : entries_) {
    out += "  " + e.label + std::string(labelWidth - e.label.size() + 2, ' ') + format(e.value);
    if (!e.unit.empty()) out += " " + e.unit;
    out += "\n";
  }
  return out;
}

nlohmann::ordered_json Stats::json() const {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const Entry& e : entries_) std::visit([&](const auto& v) { j[e.key] = v; }, e.value);
  return j;
}

}  // namespace lambert
