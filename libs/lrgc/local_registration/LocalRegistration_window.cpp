/* CLocalRegistration, the helper's share: the window patch and keyframe clouds prepared after
 * a keyframe's solve (built by whichever thread comes first, the line fits shared), the cache
 * of keyframe clouds, and the loop both threads run (parallelFor). See LocalRegistration.h. */
#include <lrgc/local_registration/LocalRegistration.h>

#include <lrgc/common/se2.h>

#include <exception>
#include <memory>
#include <mutex>

namespace lrgc
{
namespace
{
/** A keyframe's own cloud, for the pairwise links of the next keyframes (up to
 * max_pairwise_links matches): it records its noise model's fit terms. */
std::shared_ptr<const CReferenceCloud> keyframeCloudOf(const TScan2D& scan,
													   const TScanMatcherParams& p)
{
	CReferenceCloud cloud = CReferenceCloud::fromScan(scan, p);
	cloud.recordFitTerms();
	return std::make_shared<const CReferenceCloud>(std::move(cloud));
}
}  // namespace

// After a keyframe's window solve: the helper builds the patch for the next scans from a copy
// of the window (scans and poses), then the new keyframe's own cloud for the next pairwise
// links, while the mapping thread goes on. Whoever comes first builds each: a helper not yet
// running when the next scan needs the patch leaves it to the mapping thread, and the next
// scan waits for the patch only (the own cloud was 20-25 % of the job on MIT-CSAIL). The
// patch's line fits (most of its cost) are shared: a mapping thread that arrives while the
// helper runs them takes blocks of them instead of waiting.
void CLocalRegistration::prepareNextWindow(const CPoseGraph& graph, const TKeyframes& keyframes)
{
	auto job = std::make_shared<TPreparedWindow>();
	job->nodes = windowNodes();
	job->patchParams = patchParams();
	for (const size_t node : job->nodes)
	{
		job->scans.push_back(keyframes[node].scan);
		job->posesInMap.push_back(graph.pose(node));
	}
	m_helper.post(
		[job, p = m_matcherParams]
		{
			buildPatch(*job, job->patchParams, sharedFits(*job));
			buildNewestCloud(*job, p);
		});
	m_prepared = job;
	m_preparedNewest = std::move(job);
}

template <class T, class Fn>
void CLocalRegistration::buildUnlessClaimed(TPreparedWindow& job, TPreparedPart<T>& part,
											Fn&& make)
{
	if (part.claimed.exchange(true)) return;
	try
	{
		part.value = make();
	}
	catch (...)
	{
		part.error = std::current_exception();
	}
	std::lock_guard<std::mutex> lock(job.mutex);
	part.built = true;
	job.cv.notify_all();
}

template <class T>
void CLocalRegistration::waitFor(TPreparedWindow& job, TPreparedPart<T>& part)
{
	{
		std::unique_lock<std::mutex> lock(job.mutex);
		job.cv.wait(lock, [&] { return part.built; });
	}
	if (part.error) std::rethrow_exception(part.error);
}

void CLocalRegistration::buildPatch(TPreparedWindow& job, const TScanMatcherParams& p,
									const TParallelFor& parallel)
{
	buildUnlessClaimed(job, job.patch,
					   [&] { return patchOf(job.scans, job.posesInMap, p, parallel); });
}

void CLocalRegistration::waitForPatch(TPreparedWindow& job)
{
	for (;;)
	{
		std::shared_ptr<CSharedLoop> fits;
		{
			std::unique_lock<std::mutex> lock(job.mutex);
			job.cv.wait(
				lock, [&] { return job.patch.built || (job.fits && !job.fits->exhausted()); });
			if (job.patch.built) break;
			fits = job.fits;
		}
		fits->work();
	}
	if (job.patch.error) std::rethrow_exception(job.patch.error);
}

// The helper's TParallelFor for the patch's line fits: the loop is published in job.fits
// while it runs, so that a mapping thread waiting for the patch takes part (waitForPatch).
TParallelFor CLocalRegistration::sharedFits(TPreparedWindow& job)
{
	return [&job](size_t n, const std::function<void(size_t)>& fn)
	{
		auto loop = std::make_shared<CSharedLoop>(n, fn);
		{
			std::lock_guard<std::mutex> lock(job.mutex);
			job.fits = loop;
		}
		job.cv.notify_all();
		loop->work();
		loop->wait();
		std::lock_guard<std::mutex> lock(job.mutex);
		job.fits.reset();
	};
}

void CLocalRegistration::buildNewestCloud(TPreparedWindow& job, const TScanMatcherParams& p)
{
	buildUnlessClaimed(job, job.newestCloud,
					   [&] { return keyframeCloudOf(job.scans.back(), p); });
}

bool CLocalRegistration::takePreparedWindow(const CPoseGraph& graph)
{
	if (!m_prepared) return false;
	const std::shared_ptr<TPreparedWindow> job = std::move(m_prepared);
	m_prepared.reset();
	// Unless the helper has it in hand (then this thread joins its line fits).
	buildPatch(*job, job->patchParams,
			   [this](size_t n, const std::function<void(size_t)>& fn) { parallelFor(n, fn); });
	waitForPatch(*job);
	// Bit for bit the window it was built from, else it is not the patch of this window (a
	// loop closure or a new session moved or replaced nodes).
	if (windowNodes() != job->nodes) return false;
	for (size_t i = 0; i < job->nodes.size(); ++i)
	{
		const TPose2D& now = graph.pose(job->nodes[i]);
		const TPose2D& then = job->posesInMap[i];
		if (!(now.x == then.x && now.y == then.y && now.phi == then.phi)) return false;
	}
	m_cloud = std::make_shared<const CReferenceCloud>(std::move(job->patch.value));
	m_cloudNewest = job->nodes.back();
	return true;
}

void CLocalRegistration::takeNewestCloud()
{
	if (!m_preparedNewest) return;
	const std::shared_ptr<TPreparedWindow> job = std::move(m_preparedNewest);
	m_preparedNewest.reset();
	buildNewestCloud(*job, m_matcherParams);  // unless the helper has it in hand
	waitFor(*job, job->newestCloud);
	cacheKeyframeCloud(job->nodes.back(), job->newestCloud.value);  // its scan never changes
}

CLocalRegistration::TCloudPtr CLocalRegistration::keyframeCloud(size_t node,
																const TKeyframes& keyframes)
{
	for (const auto& [n, cloud] : m_keyframeClouds)
		if (n == node) return cloud;
	auto cloud = keyframeCloudOf(keyframes[node].scan, m_matcherParams);
	cacheKeyframeCloud(node, cloud);
	return cloud;
}

void CLocalRegistration::cacheKeyframeCloud(size_t node, TCloudPtr cloud)
{
	for (const auto& entry : m_keyframeClouds)
		if (entry.first == node) return;
	if (m_keyframeClouds.size() >=
		std::max(m_params.window_size, m_params.laser_only_window_size))
		m_keyframeClouds.pop_front();
	m_keyframeClouds.emplace_back(node, std::move(cloud));
}

// Each thread takes the next item nobody took yet (CSharedLoop); this one then waits only for
// the items the helper is in the middle of. A helper that starts late finds nothing left to do
// and never calls fn (so fn and what it refers to need only live until this returns).
void CLocalRegistration::parallelFor(size_t n, const std::function<void(size_t)>& fn)
{
	runShared(m_helper, n, fn);
}

}  // namespace lrgc
