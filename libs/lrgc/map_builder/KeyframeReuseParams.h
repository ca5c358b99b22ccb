/* Section [KeyframeReuse]: the parameters of CKeyframeReuse, apart from the class so that the
 * map builder's public header (MapBuilderParams.h) needs none of its internals. */
#pragma once

#include <mrpt/config/CLoadableOptions.h>

#include <cstddef>
#include <string>

namespace lrgc
{
struct TKeyframeReuseParams : public mrpt::config::CLoadableOptions
{
	bool enabled = true;  //!< no new keyframes where an existing one covers the pose
	/** [keyframes] keyframes are reused only while the newest keyframe is at most this many
	 * keyframes after the last loop link (the map there was made consistent with the robot's
	 * pose) */
	size_t trust_keyframes = 3;
	double min_inlier_fraction =
		0.5;                   //!< least fraction of the scan matched against the reused scan
	double gate_chi2 = 16.27;  //!< [chi2, 3 dof] agreement of that match with the registration

	void loadFromConfigFile(const mrpt::config::CConfigFileBase& c,
							const std::string& s) override;
	void saveToConfigFile(mrpt::config::CConfigFileBase& c,
						  const std::string& s) const override;
};

}  // namespace lrgc
