#include <gtest/gtest.h>
#include <lrgc_apps/io/PoseGraphText.h>

#include <random>
#include <sstream>

using lrgc::CPoseGraph;
using lrgc::LinkType;

namespace
{
CPoseGraph randomGraph(uint32_t seed)
{
	std::mt19937 rng(seed);
	std::uniform_real_distribution<double> u(-3, 3);
	CPoseGraph g;
	for (int i = 0; i < 20; ++i) g.addNode({u(rng), u(rng), u(rng)});
	for (size_t i = 1; i < 20; ++i)
	{
		Eigen::Matrix3d A = Eigen::Matrix3d::Random();
		g.addLink({i - 1,
				   i,
				   {u(rng), u(rng), u(rng) / 3},
				   A * A.transpose() + Eigen::Matrix3d::Identity(),
				   i % 3 == 0 ? LinkType::ScanMatch : LinkType::Odometry});
	}
	g.addLink(
		{2, 17, {0.1, -0.2, 0.3}, 1e4 * Eigen::Matrix3d::Identity(), LinkType::LoopClosure});
	g.setLinkEnabled(
		g.addLink({5, 12, {1.0 / 3, 0, 0}, Eigen::Matrix3d::Identity(), LinkType::LoopClosure}),
		false);
	return g;
}

lrgc::TSavedPoseGraph parse(const std::string& text)
{
	std::istringstream in(text);
	return lrgc::poseGraphFromText(in, "g.lrgc");
}
}  // namespace

TEST(PoseGraphText, roundTripIsBitExactWithTypesAndDisabledLinks)
{
	const CPoseGraph g = randomGraph(3);
	const auto back = parse(lrgc::poseGraphToText(g, "FRONT LASER"));
	EXPECT_EQ(back.laserLabel, "FRONT LASER");
	ASSERT_EQ(back.graph.numNodes(), g.numNodes());
	ASSERT_EQ(back.graph.numLinks(), g.numLinks());
	for (size_t i = 0; i < g.numNodes(); ++i)
	{
		EXPECT_EQ(back.graph.pose(i).x, g.pose(i).x);
		EXPECT_EQ(back.graph.pose(i).y, g.pose(i).y);
		EXPECT_EQ(back.graph.pose(i).phi, g.pose(i).phi);
	}
	for (size_t id = 0; id < g.numLinks(); ++id)
	{
		const auto &a = g.link(id), &b = back.graph.link(id);
		EXPECT_EQ(b.from, a.from);
		EXPECT_EQ(b.to, a.to);
		EXPECT_EQ(b.type, a.type);
		EXPECT_EQ(b.toInFrom.x, a.toInFrom.x);
		EXPECT_EQ(b.toInFrom.y, a.toInFrom.y);
		EXPECT_EQ(b.toInFrom.phi, a.toInFrom.phi);
		EXPECT_EQ(b.information, a.information);
		EXPECT_EQ(back.graph.isLinkEnabled(id), g.isLinkEnabled(id));
	}
	EXPECT_FALSE(back.graph.isLinkEnabled(g.numLinks() - 1));
}

TEST(PoseGraphText, badInputIsAnErrorNamingTheLine)
{
	const std::string head = "LRGC_POSE_GRAPH 1\nNODE 0 0 0 0\nNODE 1 1 0 0\n";
	const auto fails = [&](const std::string& text, const std::string& what)
	{
		try
		{
			parse(text);
			ADD_FAILURE() << "accepted: " << text;
		}
		catch (const std::exception& e)
		{
			EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
		}
	};
	fails("", "empty file");
	fails("NODE 0 0 0 0\n", "g.lrgc:1: not an lrgc pose graph");
	fails(head + "NODE 3 0 0 0\n", "g.lrgc:4: NODE 3 out of order");
	fails(head + "LINK 0 1 1 0 0 1 0 0 1 0 1 Wheel 1\n", "unknown link type 'Wheel'");
	fails(head + "LINK 0 1 1 0 0 1 0 0 1 0 1 Odometry 2\n", "g.lrgc:4: bad LINK line");
	fails(head + "LINK 0 5 1 0 0 1 0 0 1 0 1 Odometry 1\n", "out of range");
	fails(head + "LINK 0 1 1 0 0 -1 0 0 1 0 1 Odometry 1\n", "not positive definite");
	fails(head + "EDGE_SE2 0 1 1 0 0\n", "unknown record 'EDGE_SE2'");
	// Issue 30: a node 1e300 m away was taken, and the map then refused for its extent with
	// a 300-digit number.
	fails("LRGC_POSE_GRAPH 2\nNODE 0 1e300 0 0\n",
		  "g.lrgc:2: NODE 0 at (1e+300, 0, 0): not finite or farther than 1e+07 m");
	EXPECT_EQ(
		parse(head + "# comment\n\nLINK 0 1 1 0 0 1 0 0 1 0 1 Odometry 1\n").graph.numLinks(),
		1U);
}

// Issue 30: a graph.lrgc cut at a line boundary loaded silently as a smaller graph.
TEST(PoseGraphText, fileCutAtALineBoundaryIsAnError)
{
	const std::string head = "LRGC_POSE_GRAPH 2\nNODE 0 0 0 0\nNODE 1 1 0 0\n";
	const std::string link = "LINK 0 1 1 0 0 1 0 0 1 0 1 Odometry 1\n";
	EXPECT_EQ(parse(head + link + "END 2 1\n").graph.numLinks(), 1U);
	const auto fails = [&](const std::string& text, const std::string& what)
	{
		try
		{
			parse(text);
			ADD_FAILURE() << "accepted: " << text;
		}
		catch (const std::exception& e)
		{
			EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
		}
	};
	fails(head + link, "cut short after line 4 (2 nodes, 1 links read; no END line)");
	fails(head + "END 2 1\n", "END says 2 nodes and 1 links, the file has 2 and 0");
	fails(head + link + "END 2 1\n" + link, "after the END line");
	// What poseGraphToText writes ends with the END line: cut anywhere before it, it fails.
	CPoseGraph g;
	g.addNode({0, 0, 0});
	g.addNode({1, 0, 0});
	lrgc::TLink l;
	l.from = 0, l.to = 1, l.toInFrom = {1, 0, 0}, l.information = Eigen::Matrix3d::Identity();
	g.addLink(l);
	const std::string text = lrgc::poseGraphToText(g);
	// (From after the magic line on: a cut before it is an 'empty file'.)
	const size_t magicEnd = text.find('\n', text.find("LRGC_POSE_GRAPH")) + 1;
	for (size_t cut = magicEnd; cut < text.size(); cut = text.find('\n', cut) + 1)
		fails(text.substr(0, cut), "cut short");
}

// Issue 30: a version 1 file (no END line) cut at a line boundary loaded silently. Whether it
// was cut cannot be told, so it loads with a warning naming the file and its last line; a
// file of any version cut inside a line (no newline at its end) is refused.
TEST(PoseGraphText, versionOneWarnsAndACutLineIsAnError)
{
	const std::string v1 =
		"LRGC_POSE_GRAPH 1\nNODE 0 0 0 0\nNODE 1 1 0 0\n"
		"LINK 0 1 1 0 0 1 0 0 1 0 1 Odometry 1\n";
	const auto whole = parse(v1);
	EXPECT_EQ(whole.graph.numLinks(), 1U);
	EXPECT_NE(
		whole.warning.find("g.lrgc:4: a version 1 graph (no END line): whether it was "
						   "cut after this line (2 nodes, 1 links read) cannot be checked"),
		std::string::npos)
		<< whole.warning;
	const auto cut = parse(v1.substr(0, v1.find("LINK")));
	EXPECT_EQ(cut.graph.numLinks(), 0U);
	EXPECT_NE(cut.warning.find("g.lrgc:3: a version 1 graph"), std::string::npos)
		<< cut.warning;
	EXPECT_EQ(parse("LRGC_POSE_GRAPH 2\nNODE 0 0 0 0\nEND 1 0\n").warning, "")
		<< "version 2 has the END line";
	for (const std::string& text : {v1.substr(0, v1.size() - 1), v1.substr(0, v1.size() - 9),
									std::string("LRGC_POSE_GRAPH 2\nNODE 0 0 0 0\nEND 1 0")})
		try
		{
			parse(text);
			ADD_FAILURE() << "accepted a file cut inside its last line: " << text;
		}
		catch (const std::exception& e)
		{
			EXPECT_NE(std::string(e.what()).find("cut short in this line (no end of line)"),
					  std::string::npos)
				<< e.what();
		}
}

// Each node's mapping session is saved (version 3), so a map continued twice still knows which
// keyframes are newer; files of versions 1 and 2 load with every node in session 0.
TEST(PoseGraphText, sessionsRoundTripAndOlderVersionsLoadAsSessionZero)
{
	const CPoseGraph g = randomGraph(4);
	std::vector<size_t> sessions(g.numNodes(), 0);
	for (size_t i = 8; i < sessions.size(); ++i) sessions[i] = i < 14 ? 1 : 2;
	const auto back = parse(lrgc::poseGraphToText(g, "", sessions));
	EXPECT_EQ(back.sessions, sessions);
	EXPECT_EQ(parse(lrgc::poseGraphToText(g)).sessions, std::vector<size_t>(g.numNodes(), 0));
	EXPECT_EQ(parse("LRGC_POSE_GRAPH 2\nNODE 0 0 0 0\nNODE 1 1 0 0\nEND 2 0\n").sessions,
			  std::vector<size_t>({0, 0}));
	EXPECT_EQ(parse("LRGC_POSE_GRAPH 3\nNODE 0 0 0 0 0\nNODE 1 1 0 0 4\nEND 2 0\n").sessions,
			  std::vector<size_t>({0, 4}));
	const auto fails = [](const std::string& text, const std::string& expected)
	{
		try
		{
			parse(text);
			ADD_FAILURE() << "accepted: " << text;
		}
		catch (const std::exception& e)
		{
			EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
		}
	};
	fails("LRGC_POSE_GRAPH 3\nNODE 0 0 0 0\nEND 1 0\n", "g.lrgc:2: bad NODE line");
	fails("LRGC_POSE_GRAPH 3\nNODE 0 0 0 0 -1\nEND 1 0\n", "g.lrgc:2: NODE 0 of session -1");
	fails("LRGC_POSE_GRAPH 3\nNODE 0 0 0 0 1e9\nEND 1 0\n", "g.lrgc:2: bad NODE line");
	fails("LRGC_POSE_GRAPH 3\nNODE 0 0 0 0 9999999\nEND 1 0\n", "not in [0, 100000]");
	EXPECT_THROW(lrgc::poseGraphToText(g, "", {0, 1}), std::exception);
}
