#include <gtest/gtest.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <lrgc/loop_closing/PatchCorrelator.h>

#include <cmath>

using lrgc::TPatchCorrelatorParams;

TEST(PatchCorrelatorParams, TextRoundTripKeepsEveryValue)
{
	TPatchCorrelatorParams p;
	p.resolution_m = 0.04;
	p.blur_sigma_m = 0.07;
	p.angular_step = 0.006;
	p.min_score = 0.61;
	p.min_ambiguity = 1.3;
	p.max_std_xy_m = 0.15;
	p.max_std_phi = 0.03;
	p.cluster_radius_m = 0.7;
	p.cluster_radius_phi = 0.2;
	p.cluster_score_scale = 0.08;
	mrpt::config::CConfigFileMemory mem;
	p.saveToConfigFile(mem, "PatchCorrelator");
	// Through text, as a user's .ini would be.
	mrpt::config::CConfigFileMemory text(mem.getContent());
	TPatchCorrelatorParams q;
	q.loadFromConfigFile(text, "PatchCorrelator");
	EXPECT_NEAR(q.resolution_m, p.resolution_m, 1e-12);
	EXPECT_NEAR(q.blur_sigma_m, p.blur_sigma_m, 1e-12);
	EXPECT_NEAR(q.angular_step, p.angular_step, 1e-7);  // degrees written with 6 digits
	EXPECT_NEAR(q.min_score, p.min_score, 1e-12);
	EXPECT_NEAR(q.min_ambiguity, p.min_ambiguity, 1e-12);
	EXPECT_NEAR(q.max_std_xy_m, p.max_std_xy_m, 1e-12);
	EXPECT_NEAR(q.max_std_phi, p.max_std_phi, 1e-7);
	EXPECT_NEAR(q.cluster_radius_m, p.cluster_radius_m, 1e-12);
	EXPECT_NEAR(q.cluster_radius_phi, p.cluster_radius_phi, 1e-7);
	EXPECT_NEAR(q.cluster_score_scale, p.cluster_score_scale, 1e-12);
	// Keys in degrees are written in degrees.
	EXPECT_NEAR(text.read_double("PatchCorrelator", "max_std_phi_deg", 0), 0.03 * 180 / M_PI,
				1e-6);
}

TEST(PatchCorrelatorParams, UnknownKeyAndBadValueAreErrors)
{
	{
		mrpt::config::CConfigFileMemory mem("[PatchCorrelator]\nmin_scor = 0.5\n");
		TPatchCorrelatorParams p;
		try
		{
			p.loadFromConfigFile(mem, "PatchCorrelator");
			FAIL() << "misspelt key accepted";
		}
		catch (const std::exception& e)
		{
			EXPECT_NE(std::string(e.what()).find("min_score"), std::string::npos) << e.what();
		}
	}
	for (const char* bad :
		 {"min_ambiguity = 0.9", "min_score = 1.5", "resolution_m = 0", "resolution_m = 0.001",
		  "max_std_xy_m = 0", "cluster_score_scale = 0"})
	{
		mrpt::config::CConfigFileMemory mem(std::string("[PatchCorrelator]\n") + bad + "\n");
		TPatchCorrelatorParams p;
		EXPECT_THROW(p.loadFromConfigFile(mem, "PatchCorrelator"), std::exception) << bad;
	}
	TPatchCorrelatorParams p;
	p.min_ambiguity = 0.5;
	EXPECT_THROW(lrgc::CPatchCorrelator{p}, std::exception);
}

TEST(PatchCorrelatorParams, VerdictNamesTheFailingFilter)
{
	TPatchCorrelatorParams prm;
	lrgc::TCorrelationResult r;
	r.score = 0.8;
	r.ambiguity = 2;
	r.cov = Eigen::Vector3d(0.01 * 0.01, 0.02 * 0.02, 0.001 * 0.001).asDiagonal();
	EXPECT_TRUE(r.passesFilters(prm));
	using R = lrgc::TCorrelationVerdict::Reason;
	r.ambiguity = 1.05;
	auto v = r.checkFilters(prm);
	EXPECT_EQ(v.rejection, R::Ambiguous);
	EXPECT_DOUBLE_EQ(v.value, 1.05);
	EXPECT_NE(v.message().find("ambiguity 1.050 < min_ambiguity"), std::string::npos);
	r.ambiguity = 2;
	r.cov(1, 1) = 0.3 * 0.3;
	EXPECT_EQ(r.checkFilters(prm).rejection, R::SpreadXY);
	EXPECT_NEAR(r.checkFilters(prm).value, 0.3, 1e-12);
	r.cov(1, 1) = 0.01;
	r.cov(2, 2) = 0.1 * 0.1;
	EXPECT_EQ(r.checkFilters(prm).rejection, R::SpreadTheta);
	r.score = 0.3;
	EXPECT_EQ(r.checkFilters(prm).rejection, R::LowScore);
}
