// Rigid motions of bone parts and their recovery by iterative closest
// points (patient; Mollemans et al. 2007, Sec. 3.2): the planning of a patient
// is the motion that carries each bone part of the pre-operative skull onto the
// post-operative one. Closest points come from a nanoflann k-d tree over the
// fixed cloud, the best rigid fit of the pairs from Eigen's SVD (Arun, Huang
// and Blostein 1987, with the reflection fixed).

#include <softface/core/error.h>
#include <softface/patient/icp.h>

#include <Eigen/Dense>
#include <nanoflann.hpp>

#include <cmath>
#include <limits>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      using Matrix3 = Eigen::Matrix3d;
      using Vector3 = Eigen::Vector3d;

      Matrix3
      to_eigen(const std::array<double, 9> &r)
      {
        Matrix3 m;
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            m(i, j) = r[3 * i + j];
        return m;
      }

      std::array<double, 9>
      from_eigen(const Matrix3 &m)
      {
        std::array<double, 9> r;
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            r[3 * i + j] = m(i, j);
        return r;
      }

      Vector3
      to_eigen(const Vec3 &v)
      {
        return Vector3(v[0], v[1], v[2]);
      }

      Vec3
      to_vec3(const Vector3 &v)
      {
        return {{v[0], v[1], v[2]}};
      }

      // nanoflann's view of a point cloud.
      struct Cloud
      {
        const std::vector<Vec3> &points;

        std::size_t
        kdtree_get_point_count() const
        {
          return points.size();
        }
        double
        kdtree_get_pt(const std::size_t i, const std::size_t d) const
        {
          return points[i][d];
        }
        template <class BoundingBox>
        bool
        kdtree_get_bbox(BoundingBox &) const
        {
          return false;
        }
      };

      using KDTree = nanoflann::KDTreeSingleIndexAdaptor<
        nanoflann::L2_Simple_Adaptor<double, Cloud>,
        Cloud,
        3>;
    } // namespace

    Vec3
    RigidTransform::operator()(const Vec3 &x) const
    {
      return to_vec3(to_eigen(rotation) * to_eigen(x) + to_eigen(translation));
    }

    RigidTransform
    RigidTransform::after(const RigidTransform &first) const
    {
      RigidTransform t;
      t.rotation =
        from_eigen(Matrix3(to_eigen(rotation) * to_eigen(first.rotation)));
      t.translation = to_vec3(to_eigen(rotation) * to_eigen(first.translation) +
                              to_eigen(translation));
      return t;
    }

    RigidTransform
    RigidTransform::inverse() const
    {
      RigidTransform t;
      const Matrix3  rt = to_eigen(rotation).transpose();
      t.rotation        = from_eigen(rt);
      t.translation     = to_vec3(-(rt * to_eigen(translation)));
      return t;
    }

    double
    RigidTransform::angle_degrees() const
    {
      const double c = (rotation[0] + rotation[4] + rotation[8] - 1.) / 2.;
      return std::acos(std::max(-1., std::min(1., c))) * 180. / M_PI;
    }

    Vec3
    RigidTransform::axis() const
    {
      const Eigen::AngleAxisd a(to_eigen(rotation));
      return to_vec3(a.axis());
    }

    RigidTransform
    RigidTransform::from_planning(const Vec3  &translation,
                                  const Vec3  &axis,
                                  const double angle_degrees,
                                  const Vec3  &centre)
    {
      Vector3 n = to_eigen(axis);
      if (n.norm() == 0.)
        n = Vector3::UnitZ();
      const Matrix3 r =
        Eigen::AngleAxisd(angle_degrees * M_PI / 180., n.normalized())
          .toRotationMatrix();
      RigidTransform t;
      t.rotation = from_eigen(r);
      // x -> R (x - c) + c + t = R x + (c - R c + t).
      t.translation = to_vec3(to_eigen(centre) - r * to_eigen(centre) +
                              to_eigen(translation));
      return t;
    }

    IcpResult
    icp(const std::vector<Vec3> &moving,
        const std::vector<Vec3> &fixed,
        const RigidTransform    &initial,
        const IcpParameters     &prm)
    {
      if (moving.size() < 3 || fixed.size() < 3)
        throw Error("ICP: needs at least three moving and three fixed points "
                    "(got " +
                    std::to_string(moving.size()) + " and " +
                    std::to_string(fixed.size()) + ").");
      const Cloud cloud{fixed};
      KDTree      tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
      tree.buildIndex();

      IcpResult result;
      result.transform = initial;
      double rejection = prm.rejection_distance;
      for (result.iterations = 1; result.iterations <= prm.max_iterations;
           ++result.iterations)
        {
          // Pair every moved point with its closest fixed point.
          const Matrix3 r = to_eigen(result.transform.rotation);
          const Vector3 t = to_eigen(result.transform.translation);
          std::vector<std::pair<Vector3, Vector3>> pairs;
          pairs.reserve(moving.size());
          double sum_squares = 0.;
          for (const auto &p : moving)
            {
              const Vector3 x = r * to_eigen(p) + t;
              unsigned int  index;
              double        distance_squared;
              const double  query[3] = {x[0], x[1], x[2]};
              tree.knnSearch(query, 1, &index, &distance_squared);
              if (distance_squared <= rejection * rejection)
                {
                  pairs.emplace_back(to_eigen(p), to_eigen(fixed[index]));
                  sum_squares += distance_squared;
                }
            }
          if (pairs.size() < 3)
            throw Error("ICP: fewer than three point pairs lie within " +
                        number_text(rejection) +
                        " mm of each other; the start is too far off.");
          result.n_pairs = pairs.size();
          result.rms     = std::sqrt(sum_squares / pairs.size());

          // The rigid fit of the pairs: centroids, then the rotation from
          // the SVD of the cross-covariance (reflections excluded).
          Vector3 mean_moving = Vector3::Zero(), mean_fixed = Vector3::Zero();
          for (const auto &[a, b] : pairs)
            {
              mean_moving += a;
              mean_fixed += b;
            }
          mean_moving /= pairs.size();
          mean_fixed /= pairs.size();
          Matrix3 h = Matrix3::Zero();
          for (const auto &[a, b] : pairs)
            h += (a - mean_moving) * (b - mean_fixed).transpose();
          const Eigen::JacobiSVD<Matrix3> svd(h,
                                              Eigen::ComputeFullU |
                                                Eigen::ComputeFullV);
          Matrix3                         d = Matrix3::Identity();
          d(2, 2) =
            (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ?
              -1. :
              1.;
          const Matrix3 r_new = svd.matrixV() * d * svd.matrixU().transpose();
          const Vector3 t_new = mean_fixed - r_new * mean_moving;

          // How far the new motion moves any moving point from the old one.
          double step = 0.;
          for (const auto &p : moving)
            step =
              std::max(step, ((r_new - r) * to_eigen(p) + (t_new - t)).norm());
          result.transform.rotation    = from_eigen(r_new);
          result.transform.translation = to_vec3(t_new);
          if (step < prm.tolerance)
            {
              if (rejection <= prm.final_rejection_distance)
                {
                  result.converged = true;
                  break;
                }
              rejection =
                std::max(rejection / 2., prm.final_rejection_distance);
            }
        }
      if (result.iterations > prm.max_iterations)
        result.iterations = prm.max_iterations;
      return result;
    }
  } // namespace Patient
} // namespace softface
