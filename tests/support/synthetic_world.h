/* A synthetic 2D world for tests: line segments, a ray-casting laser, world builders and a
 * trajectory + noisy odometry generator. Everything is seeded, so a test is reproducible.
 *
 * Frames: world points in metres; poses are mrpt::math::TPose2D "robotInWorld" (world <-
 * robot). simulateScan() returns a lrgc::TScan2D exactly as scanFromObservation() would (valid
 * returns only, in the robot frame, sensor offset applied). No-returns (nothing within
 * maxRange, or dropped beams) are simply absent, as in a real TScan2D.
 *
 * Typical use:
 *   auto world = lrgc::test::makeRoomWorld(42);
 *   std::mt19937 rng(7);
 *   lrgc::test::TLaserSimParams laser;            // 180 deg, 361 beams, 1 cm noise
 *   auto pose = lrgc::test::sampleFreePose(world, world.bounds(), 0.5, rng);
 *   lrgc::TScan2D scan = lrgc::test::simulateScan(world, *pose, laser, rng);
 */
#pragma once

#include <lrgc/scan_matching/Scan.h>
#include <mrpt/math/TPose2D.h>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

namespace lrgc::test
{
/** What a segment is made of, for the laser (see CSyntheticWorld::castBeam). */
enum class TSurface
{
	Solid,   //!< returns every beam that reaches it
	Glass,   //!< a pane: returns a beam with probability glassReturn, else lets it through
	Railing  //!< a row of thin round posts along the segment: the beams between them go on
};

struct TSegment
{
	Eigen::Vector2d a, b;  //!< end points [m], world frame
	TSurface surface = TSurface::Solid;
	double glassReturn = 1;                    //!< Glass: share of the beams the pane returns
	double postSpacing = 0, postDiameter = 0;  //!< Railing: centre to centre, width [m]
};

/** A beam's first return: its range [m] and |cos| of the angle between the beam and the
 * surface's normal (1: head on, 0: grazing). */
struct TBeamHit
{
	double range = 0;
	double cosIncidence = 1;
};

/** Axis-aligned box [m]: used for bounds and sampling regions. */
struct TBox
{
	Eigen::Vector2d min{0, 0}, max{0, 0};
};

/** A set of line segments (walls, furniture) that reflect laser beams. */
class CSyntheticWorld
{
public:
	void addSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b);
	/** Closed polygon through the vertices (last joins first). */
	void addPolygon(const std::vector<Eigen::Vector2d>& vertices);
	/** Rectangle of half sizes (hx, hy) [m] rotated by angle [rad] about its centre. */
	void addBox(const Eigen::Vector2d& centre, double hx, double hy, double angle = 0);
	/** Regular n-gon approximating a circle (pillar, bin) of radius [m]. */
	void addCircle(const Eigen::Vector2d& centre, double radius, int sides = 16);
	/** A glass pane from a to b that returns `returnRate` of the beams reaching it and lets
	 * the others through to whatever lies behind (the far wall, or nothing). */
	void addGlass(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double returnRate);
	/** A railing from a to b: round posts of `diameter` [m] every `spacing` [m] (one at a),
	 * nothing between them at the laser's height. */
	void addRailing(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double spacing,
					double diameter);
	/** Appends all segments of another world shifted by `offset` [m]. */
	void addWorld(const CSyntheticWorld& other, const Eigen::Vector2d& offset);

	const std::vector<TSegment>& segments() const { return m_segments; }
	/** Bounding box of all segments. */
	TBox bounds() const;

	/** Distance [m] from `origin` to the first segment hit along the ray of direction `angle`
	 * [rad, world frame], or nullopt if nothing is hit within maxRange. Glass stops the ray;
	 * a railing stops it where it meets a post. */
	std::optional<double> castRay(const Eigen::Vector2d& origin, double angle,
								  double maxRange) const;
	/** castRay for one laser beam: a pane returns it if glassDraw (uniform in [0, 1), one
	 * draw per beam) is below the pane's glassReturn, else the beam passes through. */
	std::optional<TBeamHit> castBeam(const Eigen::Vector2d& origin, double angle,
									 double maxRange, double glassDraw) const;
	/** True if any segment is glass or a railing (beams that go through to the far side). */
	bool hasSeeThrough() const;
	/** Euclidean distance [m] from p to the nearest segment (infinity if empty). */
	double distanceToNearest(const Eigen::Vector2d& p) const;
	/** The segments that come within `range` [m] of `origin` (1 mm more, for rounding), in
	 * this world's order. A ray from origin meets a segment at t >= the segment's distance
	 * (|d| = 1), so castBeam(origin, ., maxRange <= range, .) finds the same crossings, in the
	 * same order, here and in the result: the same hit bit for bit, at the cost of the nearby
	 * segments only (simulateScan in a 320 m loop: ray casting was 31 % of a test's CPU). */
	CSyntheticWorld within(const Eigen::Vector2d& origin, double range) const;

private:
	std::vector<TSegment> m_segments;
};

/** The simulated laser. Defaults: a SICK LMS-like 180 deg, 361 beams, 1 cm noise. */
struct TLaserSimParams
{
	double fov_deg = 180;  //!< aperture, first to last beam, symmetric about the sensor x axis
	int beams = 361;
	double maxRange = 30;         //!< [m]; hits at or beyond it are no-returns (absent)
	double rangeNoiseStd = 0.01;  //!< Gaussian range noise [m]
	/** Probability that a beam returns a spurious range, uniform in [minRange, true range]
	 * (dust, people, glass): an outlier in front of the true surface. */
	double outlierRate = 0;
	double dropRate = 0;     //!< probability that a beam returns nothing (absent)
	double minRange = 0.05;  //!< [m] smallest valid range
	/** Max-range dropouts: a beam that hits a surface at range r with incidence cos c reads
	 * the maximum (a no-return, absent) with probability maxRangeDropRate * (r / maxRange +
	 * 1 - c): dark, far and grazing surfaces return too little light. */
	double maxRangeDropRate = 0;
	/** Mixed pixels: the beam's spot is footprint_deg wide; where its two edges hit surfaces
	 * more than 0.1 m apart in range (an edge, a post, a pane's far side), the reading is,
	 * with probability mixedPixelRate, uniform between the near and the far range. */
	double mixedPixelRate = 0;
	double footprint_deg = 0.5;
	mrpt::math::TPose2D sensorInRobot{0, 0, 0};  //!< (robot <- sensor)
};

/** Ray-casts a scan from robotInWorld. Random draws come from rng (noise, outliers, drops;
 * glass, mixed pixels and max-range dropouts only where the world or the laser has them, so
 * that a world without them sees the same noise as before they existed). */
lrgc::TScan2D simulateScan(const CSyntheticWorld& world,
						   const mrpt::math::TPose2D& robotInWorld,
						   const TLaserSimParams& laser, std::mt19937& rng);

/** Removes the points whose bearing in the robot frame lies in [from, to] [rad]: a wide gap of
 * no-return readings (an open door onto a hall beyond maxRange, a black surface). */
void removeBearingSector(lrgc::TScan2D& scan, double from_rad, double to_rad);

/** A uniformly drawn pose in `region` at least `clearance` [m] from every segment, heading
 * uniform in (-pi, pi]; nullopt after 1000 failed draws. */
std::optional<mrpt::math::TPose2D> sampleFreePose(const CSyntheticWorld& world,
												  const TBox& region, double clearance,
												  std::mt19937& rng);

// ---------------------------------------------------------------------------------------------
// World builders
// ---------------------------------------------------------------------------------------------

/** A 10 x 7 m room (corners (0,0)-(10,7)) with two pillars, an L-shaped counter, a doorway,
 * and `clutter` random short segments (furniture legs, boxes) drawn from `seed`. Geometry
 * constrains all three DOF from anywhere inside. */
CSyntheticWorld makeRoomWorld(uint32_t seed, int clutter = 8);

/** A straight featureless corridor along x: two walls y = 0 and y = width from x = 0 to
 * x = length, no end walls. From its middle with maxRange << length/2, x is unobservable. */
CSyntheticWorld makeCorridorWorld(double length = 200, double width = 2.0);

/** nx * ny identical square rooms of side `roomSize` [m] (cell (i, j) spans
 * [i*s, (i+1)*s] x [j*s, (j+1)*s]), joined by doorways of width `door` [m] centred on each
 * shared wall, each room furnished identically (a box and a pillar at the same place):
 * perceptual aliasing for loop-closing tests. */
CSyntheticWorld makeRepeatedRoomsWorld(int nx, int ny, double roomSize = 6.0,
									   double door = 1.0);

/** A wide open hall, corners (0,0)-(L,W) (default 60 x 30 m), where a long laser sees few
 * walls: the north side is a glass facade (no segments: no returns) except for 6 m of wall
 * at each end, the east end has a 12 m opening onto nothing, the south wall has `alcoves`
 * 1.5 m deep niches at seeded places, and three rows of 0.3 m pillars stand 10 m apart. */
CSyntheticWorld makeOpenHallWorld(uint32_t seed, double L = 60, double W = 30, int alcoves = 5);

/** A long museum gallery along x, corners (0,0)-(L,W), both long walls lined with identical
 * alcoves (`pitch` [m] apart, 2 m wide, 1.5 m deep) facing each other, and closed ends: from
 * inside with a laser shorter than L/2 every place looks like the one `pitch` metres on. */
CSyntheticWorld makeAlcoveGalleryWorld(double L = 80, double W = 8, double pitch = 4);

/** A museum of two parallel galleries, corners (0,0)-(L,W): outer long walls and both long
 * faces of a central block (x from 12 to L - 12, 4 m thick, across y = W / 2) lined with
 * identical niches (2 m wide, 1.5 m deep, one every `pitch` [m]), plain end walls, and six
 * 0.6 m plinths at seeded places in the end halls. A loop runs around the block through both
 * galleries and end halls, e.g. (6, 6) - (L - 6, 6) - (L - 6, W - 6) - (6, W - 6); along a
 * gallery every place looks like the one `pitch` metres on. */
CSyntheticWorld makeMuseumWorld(uint32_t seed, double L = 64, double W = 28, double pitch = 4);

/** A 100 x 60 m building, corners (0,0)-(100,60), of mixed returns for a long laser (issue 28,
 * the 80 m SICK's log): a glass-walled courtyard block (34,22)-(66,38) in the middle, whose
 * south and north faces are panes (`glassReturn` of the beams come back, the rest go on to
 * the courtyard and the hall beyond) between 0.1 m mullions every 4 m, whose east face is a
 * railing (0.05 m posts every 0.12 m) and whose west face is a wall; glass-fronted offices
 * along the north (front y = 50, partitions every 8 m, a desk in each); a railing at x = 10
 * along a stairwell void in the west hall (the outer wall 10 m behind it); niches in the
 * south wall and pillars at seeded places. A loop of 2.4 m clearance runs through the halls
 * around the block: (22,12) - (78,12) - (78,45) - (22,45). */
CSyntheticWorld makeGlassBuildingWorld(uint32_t seed, double glassReturn = 0.35);

/** The shape of makeGlassAtriumWorld: a larger building of wide halls around an atrium. */
struct TGlassAtriumShape
{
	double length = 160, width = 100;  //!< [m] outer walls, corners (0,0)-(length,width)
	double officeDepth = 10;           //!< [m] offices along the south and north outer walls
	double hall = 12;          //!< [m] hall between an office front and the atrium's railing
	double glassReturn = 0.1;  //!< share of the beams a pane returns
	double postSpacing = 0.12, postDiameter = 0.05;  //!< [m] the railings' posts
};

/** A large building of mixed returns for a long laser (issue 28, the 80 m SICK's log, at its
 * scale): an atrium void (m, m)-(length - m, width - m), m = officeDepth + hall, railed on
 * all four sides (posts of postDiameter every postSpacing, so that neighbouring beams
 * alternate between a post a few metres off and the far side of the atrium 50-80 m off),
 * with a column every 16 m (seeded offsets) along its edge and a railed bridge across its
 * middle; glass-fronted offices (panes between 0.1 m mullions every 4 m, partitions every
 * 8 m, a desk in each) along the south and north walls; a west hall with a 10 m opening in
 * the outer wall onto nothing (no returns) and a railed stairwell void along the east wall;
 * benches and plant tubs along the hall sides at seeded places. The halls' centre lines
 * form a loop (4.4 m clearance with the default shape): (m - hall / 2, officeDepth + hall / 2)
 * to (length - m + hall / 2, width - officeDepth - hall / 2). */
CSyntheticWorld makeGlassAtriumWorld(uint32_t seed, const TGlassAtriumShape& shape = {});

/** People walking through the scene: `count` circles of radius 0.25 m at seeded places in
 * `region`, each walking at a seeded 0.5-1.5 m/s in a straight line and bouncing off the
 * region's edges. at(t) [s] adds them to a copy of a world, leaving out anyone closer than
 * `keepOut` [m] to `robot` (nobody walks through the robot). */
class CCrowd
{
public:
	CCrowd(const TBox& region, int count, uint32_t seed);
	CSyntheticWorld addTo(const CSyntheticWorld& world, double t, const Eigen::Vector2d& robot,
						  double keepOut = 1.0) const;
	/** Position [m] of person i at time t [s]. */
	Eigen::Vector2d position(size_t i, double t) const;
	size_t size() const { return m_start.size(); }

private:
	TBox m_region;
	std::vector<Eigen::Vector2d> m_start, m_velocity;
};

// ---------------------------------------------------------------------------------------------
// Trajectories and odometry
// ---------------------------------------------------------------------------------------------

/** Odometry noise, proportional to motion (Thrun's alpha model, per step, standard deviations):
 *  sd_trans = a3 * |dtrans| + a4 * |drot|  [m]
 *  sd_rot   = a1 * |drot|   + a2 * |dtrans| [rad] */
struct TOdometryNoise
{
	double a1 = 0.05;  //!< [rad/rad]
	double a2 = 0.02;  //!< [rad/m]
	double a3 = 0.02;  //!< [m/m]
	double a4 = 0.01;  //!< [m/rad]
};

struct TTrajectory
{
	std::vector<mrpt::math::TPose2D> truePoses;  //!< (world <- robot) at each step
	/** Noisy odometry increments: odometryIncrements[k] is the measured motion from step k to
	 * k+1 in the frame of step k; size truePoses.size() - 1. */
	std::vector<mrpt::math::TPose2D> odometryIncrements;
	/** Dead-reckoned poses: truePoses[0] composed with the increments. */
	std::vector<mrpt::math::TPose2D> odometryPoses;
};

/** Samples poses every `step` [m] along the polyline through `waypoints` (heading along the
 * path, turning in place at corners in steps of at most `maxTurn` [rad]) and draws noisy
 * odometry increments from `seed`. Needs at least 2 waypoints. */
TTrajectory makeTrajectory(const std::vector<Eigen::Vector2d>& waypoints, double step,
						   const TOdometryNoise& noise, uint32_t seed, double maxTurn = 0.35);

/** Adds one draw of odometry noise to a true increment (the model of TOdometryNoise). */
mrpt::math::TPose2D noisyIncrement(const mrpt::math::TPose2D& trueIncrement,
								   const TOdometryNoise& noise, std::mt19937& rng);

}  // namespace lrgc::test
