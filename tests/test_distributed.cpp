// The distributed layer (distributed/): the checkpoint file refuses what is not its run's, the
// partition cuts the cluster order by cost, and a solve stopped at a checkpoint and resumed
// gives the bits of one never stopped, whether it stopped while refining or while sweeping.
// The runs on several MPI ranks are tested through the program (support/mpi_ranks.sh,
// support/checkpoint_resume.sh).
#include <radiosity/distributed/checkpoint.hpp>
#include <radiosity/distributed/partition.hpp>
#include <radiosity/hierarchy/hierarchical.hpp>
#include <radiosity/io/scenes.hpp>
#include <radiosity/mesh/subdivide.hpp>

#include <doctest/doctest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace radiosity;

namespace {

/// A fresh path in the temporary folder (removed with its .tmp on destruction).
struct TempFile {
    std::string path;
    explicit TempFile(const std::string& name)
        : path((std::filesystem::temp_directory_path() / name).string()) {
        std::filesystem::remove(path);
    }
    ~TempFile() {
        std::filesystem::remove(path);
        std::filesystem::remove(path + ".tmp");
    }
};

std::vector<char> read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_all(const std::string& path, const std::vector<char>& bytes) {
    std::ofstream(path, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
}

/// The message of the Error that f throws ("" if none).
template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// The leaves' B, band after band.
std::vector<float> radiosities(const Mesh<Rgb>& m) {
    std::vector<float> B;
    for (auto f : m.faces())
        for (std::size_t k = 0; k < 3; ++k) B.push_back(band(m.data(f).radiosity, k));
    return B;
}

}  // namespace

TEST_CASE(
    "a checkpoint reads back its sections, and refuses another run's, a cut or a changed one") {
    TempFile file("radiosity_test_checkpoint.bin");
    const std::vector<double> B{1.0, 2.5, -3.0};
    const std::vector<std::uint32_t> ids{7, 8, 9, 10};
    CheckpointWriter w;
    w.add<double>(1, B);
    w.add<std::uint32_t>(2, ids);
    w.add_value<std::uint64_t>(3, 42);
    w.write(file.path, 0xabcdef);
    CHECK_FALSE(std::filesystem::exists(file.path + ".tmp"));  // renamed into place

    const CheckpointReader r(file.path, 0xabcdef);
    CHECK(r.get<double>(1) == B);
    CHECK(r.get<std::uint32_t>(2) == ids);
    CHECK(r.value<std::uint64_t>(3) == 42);
    CHECK(error_of([&] { (void)r.get<double>(9); }).find("missing") != std::string::npos);

    CHECK(error_of([&] { CheckpointReader(file.path, 0xabcdee); }).find("another scene") !=
          std::string::npos);
    const std::vector<char> good = read_all(file.path);
    std::vector<char> cut(good.begin(), good.end() - 5);
    write_all(file.path, cut);
    CHECK(error_of([&] { CheckpointReader(file.path, 0xabcdef); }).find("truncated") !=
          std::string::npos);
    std::vector<char> changed = good;
    changed[30] ^= 0x10;  // a bit of the payload
    write_all(file.path, changed);
    CHECK(error_of([&] { CheckpointReader(file.path, 0xabcdef); }).find("corrupted") !=
          std::string::npos);
    write_all(file.path, {'h', 'e', 'l', 'l', 'o'});
    CHECK(error_of([&] { CheckpointReader(file.path, 0xabcdef); }).find("not a radiosity") !=
          std::string::npos);
    CHECK(error_of([&] { CheckpointReader(file.path + ".missing", 1); }).find("cannot open") !=
          std::string::npos);
}

TEST_CASE("a failed checkpoint write keeps the last good checkpoint") {
    TempFile file("radiosity_test_checkpoint_keep.bin");
    CheckpointWriter w;
    w.add_value<int>(1, 5);
    w.write(file.path, 1);
    const std::vector<char> before = read_all(file.path);
    // A checkpoint whose temporary file cannot be made (its folder is missing) is an Error...
    const std::string nowhere = file.path + ".d/none/state";
    CHECK(error_of([&] { w.write(nowhere, 1); }).find("cannot write") != std::string::npos);
    // ... and a write that fails leaves what was there.
    CHECK(read_all(file.path) == before);
    CHECK(CheckpointReader(file.path, 1).value<int>(1) == 5);
}

TEST_CASE("the partition cuts the cluster order where the cost reaches each rank's share") {
    const Partition even(10, 3);
    CHECK(even.positions_of(0) + even.positions_of(1) + even.positions_of(2) == 10);
    for (int r = 0; r < 3; ++r) CHECK(even.positions_of(r) >= 3);
    // One heavy root: it gets a rank of its own, the others share the rest.
    std::vector<double> cost(9, 1.0);
    cost[0] = 8.0;
    const Partition heavy(9, 2, cost);
    CHECK(heavy.owner_of_position(0) == 0);
    CHECK(heavy.positions_of(0) == 1);
    CHECK(heavy.positions_of(1) == 8);
    // Owners never decrease along the order: every rank owns one range.
    for (std::size_t i = 1; i < 9; ++i)
        CHECK(heavy.owner_of_position(i) >= heavy.owner_of_position(i - 1));
}

TEST_CASE("a solve stopped at its checkpoint and resumed gives the bits of one never stopped") {
    const Mesh<Rgb> box = subdivide(build_mesh(cornell_box<Rgb>(true)), SubdivisionOptions{});
    const HierarchicalOptions base{.link_error = 2e-5};
    std::size_t refine_reports = 0;  // progress calls of the refinement (one per round)
    const auto whole = solve_hierarchical<Rgb>(box, base, 1e-5, 0, [&](const Progress& p) {
        refine_reports += p.phase == "refine";
        return true;
    });
    REQUIRE(whole.report.converged);
    REQUIRE(refine_reports > 6);
    const std::vector<float> expected = radiosities(whole.mesh);

    struct Stop {
        std::string phase;
        std::size_t after;  // progress calls of that phase
    };
    MESSAGE(whole.report.iterations << " sweeps, " << whole.hierarchy.passes << " passes, "
                                    << refine_reports << " refinement reports");
    // In the refinement, early and late in its rounds; in the sweeps, early, midway and last.
    // The last: the stop comes with the final sweep, which also meets the tolerance (the
    // checkpoint then says the pass's sweeps are done).
    const std::size_t n = whole.report.iterations;
    for (const Stop& stop : {Stop{"refine", 3}, Stop{"refine", refine_reports - 3},
                             Stop{"solve", 4}, Stop{"solve", n / 2}, Stop{"solve", n - 1}}) {
        INFO("stopped in " << stop.phase << " after " << stop.after << " reports");
        TempFile file("radiosity_test_resume.bin");
        HierarchicalOptions o = base;
        o.checkpoint = {.file = file.path, .every_seconds = 1e9, .resume = {}};  // when stopped
        std::size_t calls = 0;
        const auto progress = [&](const Progress& p) {
            return !(p.phase == stop.phase && ++calls > stop.after);
        };
        bool stopped = false;
        try {
            stopped = solve_hierarchical<Rgb>(box, o, 1e-5, 0, progress).report.cancelled;
        } catch (const Cancelled&) {
            stopped = true;
        }
        REQUIRE(stopped);
        REQUIRE(std::filesystem::exists(file.path));
        HierarchicalOptions again = base;
        again.checkpoint.resume = file.path;
        const auto resumed = solve_hierarchical<Rgb>(box, again, 1e-5);
        CHECK(resumed.hierarchy.resumed);
        CHECK(resumed.report.converged);
        CHECK(resumed.hierarchy.links == whole.hierarchy.links);
        CHECK(resumed.report.iterations == whole.report.iterations);
        CHECK(radiosities(resumed.mesh) == expected);
        // Another tolerance is another run: its checkpoint is refused.
        CHECK(error_of([&] {
                  solve_hierarchical<Rgb>(box, again, 1e-4);
              }).find("another scene or other options") != std::string::npos);
    }
}

TEST_CASE("checkpoints taken at every safe point leave the result as it was") {
    const Mesh<Rgb> box = subdivide(build_mesh(cornell_box<Rgb>(true)), SubdivisionOptions{});
    const HierarchicalOptions base{.link_error = 1e-4};
    TempFile file("radiosity_test_every.bin");
    HierarchicalOptions o = base;
    o.checkpoint = {.file = file.path, .every_seconds = 0.0, .resume = {}};
    const auto with = solve_hierarchical<Rgb>(box, o);
    const auto without = solve_hierarchical<Rgb>(box, base);
    CHECK(with.hierarchy.checkpoints > 10);
    CHECK(without.hierarchy.checkpoints == 0);
    CHECK(radiosities(with.mesh) == radiosities(without.mesh));
    // The last one, taken in the final sweeps, resumes to the same bits too.
    HierarchicalOptions again = base;
    again.checkpoint.resume = file.path;
    CHECK(radiosities(solve_hierarchical<Rgb>(box, again).mesh) == radiosities(without.mesh));
}
