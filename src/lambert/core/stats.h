#pragma once
// Named figures counted where the work happens and printed once: as an aligned table for people
// or as JSON for machines. Entries keep the order they were added in.
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

namespace lambert {

class Stats {
 public:
  using Value = std::variant<std::int64_t, double, std::string>;
  struct Entry {
    std::string key;   // machine name, e.g. "formfactor_seconds"
    std::string label; // human label, e.g. "form factors"
    Value value;
    std::string unit;  // "s", "rays/s", "" …
  };

  void add(std::string key, std::string label, Value value, std::string unit = "");
  // Adds every entry of other, in its order.
  void append(const Stats& other);
  const std::vector<Entry>& entries() const { return entries_; }
  const Entry* find(const std::string& key) const;

  std::string table() const;
  nlohmann::ordered_json json() const;

 private:
  std::vector<Entry> entries_;
};

}  // namespace lambert
