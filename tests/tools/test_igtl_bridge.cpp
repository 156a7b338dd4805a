// The OpenIGTLink device bridge (engine/devices/igtl/igtl_device.h) on loopback, against
// xcut-igtl-play, a client on the same library playing a recorded trajectory: the cut and the
// forces match the same trajectory read from CSV; a malformed message and a lost connection hold
// the tool still and say so; a port already taken is an input error naming the field.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>

#include "engine/error.h"
#include "tests/test_helpers.h"
#ifdef XCUT_HAS_IGTL
#include "engine/devices/igtl/igtl_device.h"
#endif

namespace xcut {
namespace {

#ifdef XCUT_HAS_IGTL

namespace fs = std::filesystem;


int free_port(int salt) { return 20000 + (::getpid() * 7 + salt) % 20000; }

// Positions and times a float and a 2^-32 s stamp carry exactly (TRANSFORM is float32).
const char* kTrajectory =
    "time,x,y,z,qw,qx,qy,qz\n0,0.03125,0.0078125,0,1,0,0,0\n0.25,0.03125,0.0078125,0,1,0,0,0\n"
    "0.5,0.03125,0.015625,0,1,0,0,0\n1,0.03125,0.03125,0,1,0,0,0\n";

/// The default scene's scalpel with a sphere beside its blade (so it presses the skin), as a
/// --set of its tools: `source` says where its pose comes from.
std::string scalpel(const std::string& source) {
    return "--set 'tools=[{\"name\": \"scalpel\", \"blade\": {\"tip\": [0, 0, -0.003], \"heel\": [0, 0, 0.004]}, "
           "\"shape\": {\"type\": \"sphere\", \"radius\": 0.003, \"centre\": [0, 0.004, 0.0005]}, " + source + "}]'";
}

std::string xcut_run(const std::string& args) {
    return std::string(XCUT_BINARY) + " run " + XCUT_SOURCE_DIR + "/scenes/skin_slab.json -q " + args;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
    std::ifstream in(p);
    std::vector<std::vector<std::string>> rows;
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> row;
        std::stringstream ss(line);
        for (std::string cell; std::getline(ss, cell, ',');) row.push_back(cell);
        rows.push_back(row);
    }
    return rows;
}

TEST(IgtlBridge, StreamedTrajectoryCutsAndPressesAsTheSameTrajectoryFromCsv) {
    const fs::path dir = testing::temp_dir("igtl_sync");
    std::ofstream(dir / "traj.csv") << kTrajectory;
    const int port = free_port(1);
    std::string out_csv, out_igtl, out_client;
    ASSERT_EQ(testing::run_command(xcut_run("--steps 80 -o " + (dir / "csv").string() + " " +
                           scalpel("\"trajectory_csv\": \"" + (dir / "traj.csv").string() + "\"")), out_csv), 0) << out_csv;
    auto client = std::async(std::launch::async, [&] {
        return testing::run_command(std::string(XCUT_IGTL_PLAY) + " " + (dir / "traj.csv").string() + " --port " + std::to_string(port) +
                   " --units m --hold 1", out_client);
    });
    ASSERT_EQ(testing::run_command(xcut_run("--steps 80 -o " + (dir / "igtl").string() + " " +
                           scalpel("\"device\": {\"type\": \"igtl\", \"port\": " + std::to_string(port) +
                                   ", \"sync\": true, \"units\": \"m\", \"timeout\": 30}")), out_igtl), 0) << out_igtl;
    ASSERT_EQ(client.get(), 0) << out_client;
    EXPECT_NE(out_igtl.find("4 poses, 0 other messages, 0 malformed, 1 connections"), std::string::npos) << out_igtl;
    EXPECT_EQ(out_client.find(" 0 force messages"), std::string::npos) << "forces came back: " << out_client;
    // Every figure of every step that is not a wall time agrees: the cut, the contacts, the reaction force.
    const auto a = read_csv(dir / "csv" / "skin_slab_metrics.csv"), b = read_csv(dir / "igtl" / "skin_slab_metrics.csv");
    ASSERT_EQ(a.size(), 81u);
    ASSERT_EQ(b.size(), a.size());
    const std::vector<std::string>& header = a[0];
    int compared = 0;
    double split = 0.0, max_force = 0.0;
    for (size_t c = 0; c < header.size(); ++c) {
        if (header[c].find("_ms") != std::string::npos || header[c].find("wall") != std::string::npos) continue;
        for (size_t r = 1; r < a.size(); ++r) ASSERT_EQ(a[r][c], b[r][c]) << header[c] << " at step " << r;
        ++compared;
        for (size_t r = 1; r < a.size(); ++r) {
            if (header[c] == "elements_split") split += std::stod(a[r][c]);
            if (header[c] == "scalpel_fz_N") max_force = std::max(max_force, std::abs(std::stod(a[r][c])));
        }
    }
    EXPECT_GE(compared, 20);
    EXPECT_GT(split, 20) << "the streamed scalpel cut";
    EXPECT_GT(max_force, 1e-3) << "and pressed the skin [N]";
    fs::remove_all(dir);
}

// A live stream whose second message has a broken CRC and which closes after three: the run goes
// on to its end (exit 0), says so once each, and the tool stays at the last good pose.
TEST(IgtlBridge, MalformedMessageAndLostConnectionHoldTheTool) {
    const fs::path dir = testing::temp_dir("igtl_live");
    std::ofstream(dir / "traj.csv") << kTrajectory;
    const int port = free_port(2);
    std::string out, out_client;
    auto client = std::async(std::launch::async, [&] {
        return testing::run_command(std::string(XCUT_IGTL_PLAY) + " " + (dir / "traj.csv").string() + " --port " + std::to_string(port) +
                   " --units mm --rate 20 --corrupt 1 --close-after 3", out_client);
    });
    ASSERT_EQ(testing::run_command(xcut_run("--steps 300 --record " + (dir / "session").string() + " -o " + (dir / "out").string() + " " +
                           scalpel("\"device\": {\"type\": \"igtl\", \"port\": " + std::to_string(port) + "}")), out), 0) << out;
    ASSERT_EQ(client.get(), 0) << out_client;
    EXPECT_NE(out.find("malformed TRANSFORM"), std::string::npos) << out;
    EXPECT_NE(out.find("the connection was lost or closed"), std::string::npos) << out;
    EXPECT_NE(out.find("2 poses, 0 other messages, 1 malformed, 1 connections (1 lost)"), std::string::npos)
        << "3 sent, 1 dropped: " << out;
    const auto rows = read_csv(dir / "session" / "scalpel.csv");
    ASSERT_GT(rows.size(), 3u);
    const auto& last = rows.back();  // pose 2 of the file, sent in mm (the device's default units)
    EXPECT_EQ(std::stod(last[1]), 0.03125);
    EXPECT_EQ(std::stod(last[2]), 0.015625);
    EXPECT_EQ(std::stod(last[3]), 0.0);
    fs::remove_all(dir);
}

// In sync the run keeps the peer's time: with no peer it waits (saying so) and stops when none
// connects in connect_timeout; a peer that falls behind (poses 0.5 s of wall time apart, timeout
// 0.1 s) stops the run with the stamp it waited for, instead of holding the tool and drifting apart.
TEST(IgtlBridge, SyncWaitsForThePeerOrStopsTheRun) {
    const fs::path dir = testing::temp_dir("igtl_wait");
    std::ofstream(dir / "traj.csv") << kTrajectory;
    const int port = free_port(4);
    const std::string device = "\"device\": {\"type\": \"igtl\", \"port\": " + std::to_string(port) + ", \"sync\": true, \"units\": \"m\"";
    std::string out;
    EXPECT_EQ(testing::run_command(xcut_run("--steps 5 -o " + (dir / "none").string() + " " +
                                            scalpel(device + ", \"connect_timeout\": 0.3}")), out), 2) << out;
    EXPECT_NE(out.find("waiting for the OpenIGTLink peer (listening on port " + std::to_string(port)), std::string::npos) << out;
    EXPECT_NE(out.find("tools[0].device.connect_timeout: no OpenIGTLink peer connected within 0.3 s"), std::string::npos) << out;
    std::string out_client;
    auto client = std::async(std::launch::async, [&] {
        return testing::run_command(std::string(XCUT_IGTL_PLAY) + " " + (dir / "traj.csv").string() + " --port " +
                                        std::to_string(port) + " --units m --rate 2",
                                    out_client);
    });
    EXPECT_EQ(testing::run_command(xcut_run("--steps 50 -o " + (dir / "slow").string() + " " +
                                            scalpel(device + ", \"timeout\": 0.1}")), out), 2) << out;
    client.get();
    EXPECT_NE(out.find("tools[0].device.timeout: no pose stamped at"), std::string::npos) << out;
    EXPECT_NE(out.find("sync stops the run rather than let the tool and the stream drift apart"), std::string::npos) << out;
    fs::remove_all(dir);
}

TEST(IgtlBridge, APortAlreadyTakenNamesTheField) {
    DeviceSpec spec;
    spec.type = "igtl", spec.file = "scene.json", spec.field = "tools[0].device", spec.port = free_port(3);
    IgtlDevice first(spec, "a", Keyframe{});
    try {
        IgtlDevice second(spec, "b", Keyframe{});
        ADD_FAILURE() << "two devices listened on one port";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("scene.json: tools[0].device.port: cannot listen on port"), std::string::npos)
            << e.what();
    }
}

#else

TEST(IgtlBridge, BuiltWithoutOpenIGTLinkTheSceneSaysSo) {
    GTEST_SKIP() << "this build has no OpenIGTLink (XCUT_IGTL=OFF)";
}

#endif

}  // namespace
}  // namespace xcut
