#include <lrgc/loop_closing/LoopWork.h>

namespace lrgc
{
namespace
{
// Fitted coefficients (see LoopWork.h) [ms per count].
constexpr double kJob = 0.0303, kNewScan = 0.0394;  // a_j + a_g, b_j
constexpr double kGateNode = 1.53e-3, kGateLabel = 1.63e-4;
constexpr double kCorrelation = 1.83, kAngleCell = 2.79e-5, kPoseCell = 1.01e-6;
constexpr double kMatch = 1.39, kMatchRefPoint = 2.42e-4;
constexpr double kFarMapPoint = 1.2e-5;
constexpr double kSolveElement = 1.95e-3, kSolveIterationElement = 1.11e-3;
}  // namespace

double TLoopWork::referenceMs() const
{
	return kJob * double(jobs) + kNewScan * double(newScans) +
		   kGateNode * double(gatePropagatedNodes) + kGateLabel * double(gateReusedLabels) +
		   kCorrelation * double(correlations) + kAngleCell * correlationAngleCells +
		   kPoseCell * correlationPoseCells + kMatch * double(matches) +
		   kMatchRefPoint * double(matchRefPoints) + kFarMapPoint * double(farMapPoints) +
		   kSolveElement * solveElements + kSolveIterationElement * solveIterationElements;
}

TLoopWork& TLoopWork::operator+=(const TLoopWork& o)
{
	jobs += o.jobs, newScans += o.newScans;
	gatePropagatedNodes += o.gatePropagatedNodes, gateReusedLabels += o.gateReusedLabels;
	correlations += o.correlations;
	correlationAngleCells += o.correlationAngleCells;
	correlationPoseCells += o.correlationPoseCells;
	matches += o.matches, matchRefPoints += o.matchRefPoints;
	farMapPoints += o.farMapPoints;
	solveElements += o.solveElements, solveIterationElements += o.solveIterationElements;
	return *this;
}

TLoopWork TLoopWork::operator-(const TLoopWork& o) const
{
	TLoopWork d = *this;
	d.jobs -= o.jobs, d.newScans -= o.newScans;
	d.gatePropagatedNodes -= o.gatePropagatedNodes, d.gateReusedLabels -= o.gateReusedLabels;
	d.correlations -= o.correlations;
	d.correlationAngleCells -= o.correlationAngleCells;
	d.correlationPoseCells -= o.correlationPoseCells;
	d.matches -= o.matches, d.matchRefPoints -= o.matchRefPoints;
	d.farMapPoints -= o.farMapPoints;
	d.solveElements -= o.solveElements, d.solveIterationElements -= o.solveIterationElements;
	return d;
}

}  // namespace lrgc
