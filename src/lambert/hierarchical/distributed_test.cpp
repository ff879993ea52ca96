// A distributed solve through the library (RadiosityOptions::communicator, docs/distributed.md),
// its ranks as threads of this process meeting in an in-process Communicator: no MPI, so it runs
// wherever the tests do, the sanitizers' builds included. tests/distributed_test.sh runs the same
// through mpirun and the CLI.
#include <gtest/gtest.h>

#include <barrier>
#include <cstring>
#include <memory>
#include <thread>
#include <variant>
#include <vector>

#include "lambert/core/communicator.h"
#include "lambert/engine/radiosity.h"
#include "lambert/scene/builtin.h"
#include "tests/support/engines.h"

namespace lambert {
namespace {

// Every rank posts what it holds, all wait at a barrier, each reads the others', all wait again
// before the next call may post.
struct Meeting {
  explicit Meeting(int ranks) : size(ranks), arrived(ranks), posted(static_cast<std::size_t>(ranks)) {}
  int size;
  std::barrier<> arrived;
  std::vector<const void*> posted;
};

class ThreadCommunicator final : public Communicator {
 public:
  ThreadCommunicator(int rank, std::shared_ptr<Meeting> meeting) : rank_(rank), meeting_(std::move(meeting)) {}
  int rank() const override { return rank_; }
  int size() const override { return meeting_->size; }
  void allGatherRecords(const void* mine, std::span<const int> counts, void* all, std::size_t recordBytes) override {
    meet(mine, [&] {
      auto* out = static_cast<unsigned char*>(all);
      for (int r = 0; r < size(); ++r) {
        const std::size_t bytes = static_cast<std::size_t>(counts[static_cast<std::size_t>(r)]) * recordBytes;
        if (bytes > 0) std::memcpy(out, meeting_->posted[static_cast<std::size_t>(r)], bytes);
        out += bytes;
      }
    });
    ++stats_.calls;
  }
  void maxAll(std::span<double> values) override {
    const std::vector<double> mine(values.begin(), values.end());
    meet(mine.data(), [&] {
      for (int r = 0; r < size(); ++r)
        for (std::size_t i = 0; i < values.size(); ++i)
          values[i] = std::max(values[i], static_cast<const double*>(meeting_->posted[static_cast<std::size_t>(r)])[i]);
    });
    ++stats_.calls;
  }
  Status agree(const Status& mine) override {
    Status agreed = Ok{};
    meet(&mine, [&] {
      for (int r = size(); r-- > 0;)
        if (const auto* status = static_cast<const Status*>(meeting_->posted[static_cast<std::size_t>(r)]); !*status)
          agreed = Error{"rank " + std::to_string(r) + ": " + status->error().message};
    });
    ++stats_.calls;
    return agreed;
  }

 private:
  template <class Read>
  void meet(const void* mine, const Read& read) {
    meeting_->posted[static_cast<std::size_t>(rank_)] = mine;
    meeting_->arrived.arrive_and_wait();
    read();
    meeting_->arrived.arrive_and_wait();
  }
  int rank_;
  std::shared_ptr<Meeting> meeting_;
};

RadiosityOptions jacobiOptions() {
  RadiosityOptions options = testing::quietOptions();
  options.solver = SolverKind::Jacobi;
  options.tolerance = 1e-6;
  return options;
}

// What rank 0 of a distributed solve, or one process, gives out: B per element, B at the
// vertices, the irradiance at points on the floor.
struct Outputs {
  std::vector<Rgb> radiosity, vertices, points;
  std::int64_t links = 0, linksHeld = 0;
};

std::vector<SurfacePoint> floorPoints(const Scene& scene) {
  std::vector<SurfacePoint> points;
  for (std::uint32_t s = 0; s < scene.surfaces.size(); ++s)
    if (scene.surfaces[s].name == "floor")
      for (double x : {100.0, 280.0, 450.0})
        for (double z : {80.0, 300.0, 520.0}) points.push_back({{x, 0.0, z}, {0, 1, 0}, s, 0});
  EXPECT_FALSE(points.empty());
  return points;
}

Outputs outputsOf(Radiosity& engine, const Scene& scene) {
  Outputs out;
  out.radiosity = engine.solution().radiosity();
  out.vertices = engine.solution().vertexValues(VertexQuantity::Radiosity);
  Result<std::vector<Rgb>> points = engine.solution().pointIrradiance(floorPoints(scene));
  EXPECT_TRUE(points.ok()) << points.error().message;
  if (points.ok()) out.points = *points;
  const Stats stats = engine.stats();
  out.links = testing::statCount(stats, "links");
  out.linksHeld = engine.options().communicator ? testing::statCount(stats, "rank_links") : out.links;
  return out;
}

void expectIdentical(const std::vector<Rgb>& a, const std::vector<Rgb>& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  std::size_t differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) differing += !(a[i].r == b[i].r && a[i].g == b[i].g && a[i].b == b[i].b);
  EXPECT_EQ(differing, 0u) << what << ": " << differing << " of " << a.size() << " differ";
}

TEST(DistributedTest, ThreeRanksThroughTheLibraryGiveOneProcessesSolutionToTheBit) {
  const Scene scene = cornellBoxWithSpots();
  auto one = Radiosity::create(scene, jacobiOptions());
  ASSERT_TRUE(one.ok()) << one.error().message;
  ASSERT_TRUE((*one)->solve().ok());
  const Outputs alone = outputsOf(**one, scene);

  constexpr int kRanks = 3;
  auto meeting = std::make_shared<Meeting>(kRanks);
  std::vector<std::vector<Rgb>> radiosityOfRank(kRanks);
  Outputs rankZero;
  std::vector<std::thread> ranks;
  for (int r = 0; r < kRanks; ++r)
    ranks.emplace_back([&, r] {
      RadiosityOptions options = jacobiOptions();
      options.communicator = std::make_shared<ThreadCommunicator>(r, meeting);
      auto engine = Radiosity::create(scene, options);
      ASSERT_TRUE(engine.ok()) << engine.error().message;  // alike on every rank: none waits alone
      ASSERT_TRUE((*engine)->solve().ok());
      radiosityOfRank[static_cast<std::size_t>(r)] = (*engine)->solution().radiosity();
      if (r == 0) {
        const DistributedOutputs lead = (*engine)->leadDistributedOutputs();
        rankZero = outputsOf(**engine, scene);
      } else {
        (*engine)->serveDistributedOutputs();
      }
    });
  for (std::thread& t : ranks) t.join();

  for (int r = 0; r < kRanks; ++r) expectIdentical(radiosityOfRank[static_cast<std::size_t>(r)], alone.radiosity, "radiosity");
  expectIdentical(rankZero.vertices, alone.vertices, "vertex radiosity");
  expectIdentical(rankZero.points, alone.points, "irradiance at floor points");
  // The same links, each held by the ranks under its receiver only.
  EXPECT_EQ(rankZero.links, alone.links);
  EXPECT_LT(rankZero.linksHeld, alone.links * 2 / 3);
  EXPECT_GT(rankZero.linksHeld, 0);
}

}  // namespace
}  // namespace lambert
