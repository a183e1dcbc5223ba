// Rigid registration of the post-operative CT to the pre-operative one by
// mutual information on an unaltered subvolume (Mollemans et al. 2007, 3.5.1,
// after Maes et al. 1997) with ITK's registration framework v4, and the
// motion it finds applied to surfaces (transform_surface) and volumes
// (resample). Compiled at -O2 even in this directory without deal.II's flags
// (see CMakeLists.txt): ITK's templates are instantiated here.

#include <softface/core/error.h>
#include <softface/patient/registration.h>

#include "itk_volume.h"

#include <itkCenteredTransformInitializer.h>
#include <itkCommand.h>
#include <itkConjugateGradientLineSearchOptimizerv4.h>
#include <itkImage.h>
#include <itkImageMaskSpatialObject.h>
#include <itkImageRegistrationMethodv4.h>
#include <itkLinearInterpolateImageFunction.h>
#include <itkMattesMutualInformationImageToImageMetricv4.h>
#include <itkRegionOfInterestImageFilter.h>
#include <itkRegistrationParameterScalesFromPhysicalShift.h>
#include <itkRegularStepGradientDescentOptimizerv4.h>
#include <itkResampleImageFilter.h>
#include <itkVersorRigid3DTransform.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      using FloatImage = itk::Image<float, 3>;
      using MaskImage  = itk::Image<std::uint8_t, 3>;
      using Transform  = itk::VersorRigid3DTransform<double>;
      using Metric =
        itk::MattesMutualInformationImageToImageMetricv4<FloatImage,
                                                         FloatImage>;
      using GradientDescent = itk::GradientDescentOptimizerv4Template<double>;
      using RegularStep = itk::RegularStepGradientDescentOptimizerv4<double>;
      using ConjugateGradient =
        itk::ConjugateGradientLineSearchOptimizerv4Template<double>;
      using Registration =
        itk::ImageRegistrationMethodv4<FloatImage, FloatImage, Transform>;
      using Scales = itk::RegistrationParameterScalesFromPhysicalShift<Metric>;

      std::string
      number(const double x)
      {
        std::ostringstream s;
        s << x;
        return s.str();
      }

      std::string
      interval(const double a, const double b)
      {
        return "[" + number(a) + ", " + number(b) + "]";
      }

      std::string
      describe(const Box &box)
      {
        return interval(box.lower[0], box.upper[0]) + " x " +
               interval(box.lower[1], box.upper[1]) + " x " +
               interval(box.lower[2], box.upper[2]) + " mm";
      }

      // The CT as a float image, with @p shift added and values below
      // @p floor raised to it (the moments initializer needs masses >= 0).
      FloatImage::Pointer
      float_image(const CTVolume &volume,
                  const double    shift = 0.,
                  const double    floor = -std::numeric_limits<double>::max())
      {
        Volume<float> v;
        v.reinit_like(volume);
        for (std::size_t i = 0; i < v.n_voxels(); ++i)
          v.values[i] = std::max(floor, volume.values[i] + shift);
        return to_itk(v);
      }

      // The physical extent of a volume's voxel centres.
      Box
      extent(const CTVolume &volume)
      {
        Box b;
        b.lower.fill(std::numeric_limits<double>::max());
        b.upper.fill(-std::numeric_limits<double>::max());
        for (const std::size_t i : {std::size_t(0), volume.size[0] - 1})
          for (const std::size_t j : {std::size_t(0), volume.size[1] - 1})
            for (const std::size_t k : {std::size_t(0), volume.size[2] - 1})
              {
                const Vec3 x = volume.point(i, j, k);
                for (unsigned int d = 0; d < 3; ++d)
                  {
                    b.lower[d] = std::min(b.lower[d], x[d]);
                    b.upper[d] = std::max(b.upper[d], x[d]);
                  }
              }
        return b;
      }

      void
      check_volume(const CTVolume &volume, const std::string &name)
      {
        for (unsigned int d = 0; d < 3; ++d)
          if (volume.size[d] < 2)
            throw Error("register: the " + name + " CT has " +
                        std::to_string(volume.size[d]) +
                        " voxels in direction " + std::to_string(d) +
                        "; it needs a 3D volume.");
        if (volume.values.size() != volume.n_voxels())
          throw Error("register: the " + name + " CT holds " +
                      std::to_string(volume.values.size()) + " values for " +
                      std::to_string(volume.n_voxels()) + " voxels.");
        for (unsigned int d = 0; d < 3; ++d)
          if (!(volume.spacing[d] > 0.) || !std::isfinite(volume.spacing[d]))
            throw Error("register: the " + name +
                        " CT has a voxel spacing of " +
                        number(volume.spacing[d]) + " mm.");
      }

      // The voxels of @p volume whose centres lie in @p box (the index
      // bounding box of its corners, for a volume not aligned with the
      // axes), as [lower, upper] indices; an Error if there are none.
      std::array<std::array<std::size_t, 3>, 2>
      voxels_in(const CTVolume &volume, const Box &box)
      {
        Vec3 lo, hi;
        lo.fill(std::numeric_limits<double>::max());
        hi.fill(-std::numeric_limits<double>::max());
        for (const double x : {box.lower[0], box.upper[0]})
          for (const double y : {box.lower[1], box.upper[1]})
            for (const double z : {box.lower[2], box.upper[2]})
              {
                const Vec3 c = volume.continuous_index({{x, y, z}});
                for (unsigned int d = 0; d < 3; ++d)
                  {
                    lo[d] = std::min(lo[d], c[d]);
                    hi[d] = std::max(hi[d], c[d]);
                  }
              }
        std::array<std::array<std::size_t, 3>, 2> region;
        for (unsigned int d = 0; d < 3; ++d)
          {
            // Tolerant to round-off: a box edge on a voxel centre holds it.
            const double first = std::max(0., std::ceil(lo[d] - 1e-6));
            const double last =
              std::min(double(volume.size[d] - 1), std::floor(hi[d] + 1e-6));
            if (!(first <= last))
              throw Error("register: the subvolume " + describe(box) +
                          " lies outside the pre-operative CT, whose voxel "
                          "centres span " +
                          describe(extent(volume)) + ".");
            region[0][d] = static_cast<std::size_t>(first);
            region[1][d] = static_cast<std::size_t>(last);
          }
        return region;
      }

      // The first step of level @p l (see RegistrationParameters).
      double
      level_learning_rate(const RegistrationParameters &prm,
                          const std::size_t             l)
      {
        return prm.learning_rate * prm.shrink_factors[l] /
               prm.shrink_factors[0];
      }

      RigidTransform
      rigid(const Transform &transform)
      {
        RigidTransform t;
        const auto     m = transform.GetMatrix();
        const auto     o = transform.GetOffset();
        for (unsigned int i = 0; i < 3; ++i)
          {
            for (unsigned int j = 0; j < 3; ++j)
              t.rotation[3 * i + j] = m[i][j];
            t.translation[i] = o[i];
          }
        return t;
      }
      /// Checks the schedule and the optimiser's settings; returns the
      /// coarsest shrink factor.
      unsigned int
      check_schedule(const RegistrationParameters &prm)
      {
        const std::size_t n_levels = prm.shrink_factors.size();
        if (n_levels == 0 || prm.smoothing_sigmas.size() != n_levels)
          throw Error("register: the schedule has " + std::to_string(n_levels) +
                      " shrink factors and " +
                      std::to_string(prm.smoothing_sigmas.size()) +
                      " smoothing sigmas; it needs one or more levels with "
                      "one of each.");
        unsigned int coarsest = 1;
        for (std::size_t l = 0; l < n_levels; ++l)
          {
            if (prm.shrink_factors[l] < 1 || !(prm.smoothing_sigmas[l] >= 0.))
              throw Error(
                "register: level " + std::to_string(l + 1) +
                " has shrink factor " + std::to_string(prm.shrink_factors[l]) +
                " and smoothing sigma " + number(prm.smoothing_sigmas[l]) +
                "; they must be >= 1 and >= 0.");
            coarsest = std::max(coarsest, prm.shrink_factors[l]);
          }
        if (prm.histogram_bins < 5 || prm.threads < 1 ||
            prm.max_iterations < 1 || !(prm.learning_rate > 0.) ||
            !(prm.minimum_step > 0.) ||
            !(prm.relaxation > 0. && prm.relaxation < 1.))
          throw Error("register: the optimiser needs at least 5 histogram "
                      "bins, 1 thread and 1 iteration, a positive learning "
                      "rate and minimum step, and a relaxation in (0, 1).");
        return coarsest;
      }

      /**
       * The subvolume's voxels in the pre-operative CT, at least 4 across
       * at the @p coarsest shrink factor; their count and physical extent
       * (voxel centres) go into @p result.
       */
      FloatImage::RegionType
      subvolume_region(const CTVolume               &pre_operative,
                       const RegistrationParameters &prm,
                       const unsigned int            coarsest,
                       RegistrationResult           &result)
      {
        Box box = extent(pre_operative);
        if (prm.subvolume)
          {
            if (prm.subvolume->empty())
              throw Error("register: the subvolume " +
                          describe(*prm.subvolume) + " is empty.");
            box = *prm.subvolume;
          }
        const auto             bounds = voxels_in(pre_operative, box);
        FloatImage::RegionType region;
        for (unsigned int d = 0; d < 3; ++d)
          {
            region.SetIndex(d, bounds[0][d]);
            region.SetSize(d, bounds[1][d] - bounds[0][d] + 1);
            result.subvolume_voxels[d] = region.GetSize(d);
          }
        for (unsigned int d = 0; d < 3; ++d)
          if (result.subvolume_voxels[d] < 4 * coarsest)
            throw Error("register: the subvolume " + describe(box) + " holds " +
                        std::to_string(result.subvolume_voxels[0]) + " x " +
                        std::to_string(result.subvolume_voxels[1]) + " x " +
                        std::to_string(result.subvolume_voxels[2]) +
                        " voxels of the pre-operative CT; shrink factor " +
                        std::to_string(coarsest) + " needs at least " +
                        std::to_string(4 * coarsest) +
                        " across in every direction.");
        const Vec3 a =
          pre_operative.point(bounds[0][0], bounds[0][1], bounds[0][2]);
        const Vec3 b =
          pre_operative.point(bounds[1][0], bounds[1][1], bounds[1][2]);
        for (unsigned int d = 0; d < 3; ++d)
          {
            result.subvolume.lower[d] = std::min(a[d], b[d]);
            result.subvolume.upper[d] = std::max(a[d], b[d]);
          }
        return region;
      }

      /**
       * The start: the initializer's translation (no rotation), turning
       * about the subvolume's centre, where rotation and translation are
       * least coupled.
       */
      Transform::Pointer
      initial_transform(const CTVolume               &pre_operative,
                        const CTVolume               &post_operative,
                        const FloatImage::Pointer    &pre,
                        const FloatImage::Pointer    &post,
                        const RegistrationParameters &prm,
                        const Box                    &subvolume)
      {
        auto transform = Transform::New();
        if (prm.initializer != RegistrationParameters::Initializer::identity)
          {
            using Initializer = itk::
              CenteredTransformInitializer<Transform, FloatImage, FloatImage>;
            auto initializer = Initializer::New();
            initializer->SetTransform(transform);
            if (prm.initializer ==
                RegistrationParameters::Initializer::geometry)
              {
                initializer->SetFixedImage(pre);
                initializer->SetMovingImage(post);
                initializer->GeometryOn();
              }
            else
              {
                initializer->SetFixedImage(
                  float_image(pre_operative, 1000., 0.));
                initializer->SetMovingImage(
                  float_image(post_operative, 1000., 0.));
                initializer->MomentsOn();
              }
            initializer->InitializeTransform();
          }
        const Transform::OutputVectorType start = transform->GetTranslation();
        transform->SetIdentity();
        Transform::InputPointType centre;
        for (unsigned int d = 0; d < 3; ++d)
          centre[d] = subvolume.centre()[d];
        transform->SetCenter(centre);
        transform->SetTranslation(start);
        return transform;
      }

      /**
       * Mattes mutual information on the subvolume @p region of @p pre:
       * with Restriction::mask through a mask image (kept in @p mask while
       * the metric uses it); with crop the fixed image is cropped instead
       * (fixed_image()).
       */
      Metric::Pointer
      make_metric(const RegistrationParameters &prm,
                  const FloatImage::Pointer    &pre,
                  const FloatImage::RegionType &region,
                  MaskImage::Pointer           &mask)
      {
        auto metric = Metric::New();
        metric->SetNumberOfHistogramBins(prm.histogram_bins);
        // Gradients by central differences where the metric needs them,
        // not as whole gradient images.
        metric->SetUseMovingImageGradientFilter(false);
        metric->SetUseFixedImageGradientFilter(false);
        metric->SetMaximumNumberOfWorkUnits(prm.threads);
        if (prm.restriction == RegistrationParameters::Restriction::mask)
          {
            mask = MaskImage::New();
            mask->CopyInformation(pre);
            mask->SetRegions(pre->GetLargestPossibleRegion());
            mask->Allocate(true);
            for (itk::ImageRegionIterator<MaskImage> it(mask, region);
                 !it.IsAtEnd();
                 ++it)
              it.Set(1);
            auto object = itk::ImageMaskSpatialObject<3>::New();
            object->SetImage(mask);
            object->Update();
            metric->SetFixedImageMask(object);
          }
        return metric;
      }

      /// The fixed image: @p pre, or its subvolume with Restriction::crop.
      FloatImage::Pointer
      fixed_image(const RegistrationParameters &prm,
                  const FloatImage::Pointer    &pre,
                  const FloatImage::RegionType &region)
      {
        if (prm.restriction != RegistrationParameters::Restriction::crop)
          return pre;
        auto crop =
          itk::RegionOfInterestImageFilter<FloatImage, FloatImage>::New();
        crop->SetInput(pre);
        crop->SetRegionOfInterest(region);
        crop->Update();
        FloatImage::Pointer fixed = crop->GetOutput();
        fixed->DisconnectPipeline();
        return fixed;
      }

      /**
       * The parameters' scales from the physical shift at the subvolume's
       * corners, for the mask too: at the corners of its virtual domain,
       * the whole CT, a rotation moves points so far that its steps become
       * too small to converge in 300 iterations.
       */
      Scales::Pointer
      make_scales(const Metric::Pointer &metric, const Box &subvolume)
      {
        auto scales = Scales::New();
        scales->SetMetric(metric);
        scales->SetTransformForward(true);
        auto        corners = Scales::VirtualPointSetType::New();
        std::size_t n       = 0;
        for (const double x : {subvolume.lower[0], subvolume.upper[0]})
          for (const double y : {subvolume.lower[1], subvolume.upper[1]})
            for (const double z : {subvolume.lower[2], subvolume.upper[2]})
              {
                Scales::VirtualPointType p;
                p[0] = x;
                p[1] = y;
                p[2] = z;
                corners->SetPoint(n++, p);
              }
        scales->SetVirtualDomainPointSet(corners);
        return scales;
      }

      GradientDescent::Pointer
      make_optimizer(const RegistrationParameters &prm,
                     const Scales::Pointer        &scales)
      {
        GradientDescent::Pointer optimizer;
        if (prm.optimizer == RegistrationParameters::Optimizer::regular_step)
          {
            auto o = RegularStep::New();
            o->SetLearningRate(prm.learning_rate);
            o->SetMinimumStepLength(prm.minimum_step);
            o->SetRelaxationFactor(prm.relaxation);
            o->SetGradientMagnitudeTolerance(1e-8);
            optimizer = o;
          }
        else
          {
            auto o = ConjugateGradient::New();
            // Each line search brackets [0, 2] times the step that moves no
            // voxel by more than learning_rate mm.
            o->SetLearningRate(1.);
            o->SetMaximumStepSizeInPhysicalUnits(prm.learning_rate);
            o->SetDoEstimateLearningRateOnce(true);
            o->SetDoEstimateLearningRateAtEachIteration(false);
            o->SetLowerLimit(0.);
            o->SetUpperLimit(2.);
            o->SetEpsilon(0.01);
            o->SetMaximumLineSearchIterations(20);
            o->SetMinimumConvergenceValue(prm.convergence);
            o->SetConvergenceWindowSize(prm.convergence_window);
            optimizer = o;
          }
        optimizer->SetNumberOfIterations(prm.max_iterations);
        optimizer->SetScalesEstimator(scales);
        optimizer->SetNumberOfWorkUnits(prm.threads);
        return optimizer;
      }

      /**
       * The multi-resolution schedule: shrink factors, smoothing (mm) and
       * sampling, every k-th voxel of a level where it holds more than
       * prm.samples (regular, jittered by a fixed seed).
       */
      void
      set_schedule(Registration                     &registration,
                   const RegistrationParameters     &prm,
                   const std::array<std::size_t, 3> &subvolume_voxels)
      {
        const std::size_t n_levels = prm.shrink_factors.size();
        registration.SetNumberOfLevels(n_levels);
        Registration::ShrinkFactorsArrayType   shrink(n_levels);
        Registration::SmoothingSigmasArrayType sigmas(n_levels);
        for (std::size_t l = 0; l < n_levels; ++l)
          {
            shrink[l] = prm.shrink_factors[l];
            sigmas[l] = prm.smoothing_sigmas[l];
          }
        registration.SetShrinkFactorsPerLevel(shrink);
        registration.SetSmoothingSigmasPerLevel(sigmas);
        registration.SetSmoothingSigmasAreSpecifiedInPhysicalUnits(true);
        Registration::MetricSamplingPercentageArrayType fraction(n_levels);
        bool                                            sampled = false;
        for (std::size_t l = 0; l < n_levels; ++l)
          {
            double n = 1.;
            for (unsigned int d = 0; d < 3; ++d)
              n *=
                std::ceil(double(subvolume_voxels[d]) / prm.shrink_factors[l]);
            fraction[l] = prm.samples == 0 ? 1. : std::min(1., prm.samples / n);
            sampled     = sampled || fraction[l] < 1.;
          }
        if (sampled)
          {
            registration.SetMetricSamplingStrategy(
              Registration::MetricSamplingStrategyEnum::REGULAR);
            registration.SetMetricSamplingPercentagePerLevel(fraction);
            registration.MetricSamplingReinitializeSeed(prm.seed);
          }
        else
          registration.SetMetricSamplingStrategy(
            Registration::MetricSamplingStrategyEnum::NONE);
      }

      /// What the observers of each level's start and end read and fill;
      /// it must outlive the registration's Update().
      struct LevelObservers
      {
        Registration                   *registration;
        GradientDescent                *optimizer;
        const RegistrationParameters   *prm;
        std::vector<RegistrationLevel> *levels;
      };

      /**
       * Each level starts with the registration's
       * MultiResolutionIterationEvent: its first step scaled by its shrink
       * factor over the first level's (a coarse voxel's worth), so that a
       * fine level does not jump off the coarse result. Each ends with the
       * optimiser's EndEvent: its figures into *levels.
       */
      void
      observe_levels(LevelObservers &observers)
      {
        auto level_start = itk::CStyleCommand::New();
        level_start->SetClientData(&observers);
        level_start->SetCallback(
          [](itk::Object *, const itk::EventObject &, void *data) {
            const auto  *c = static_cast<LevelObservers *>(data);
            const double step =
              level_learning_rate(*c->prm, c->registration->GetCurrentLevel());
            if (auto *o = dynamic_cast<RegularStep *>(c->optimizer))
              o->SetLearningRate(step);
            else if (auto *o = dynamic_cast<ConjugateGradient *>(c->optimizer))
              o->SetMaximumStepSizeInPhysicalUnits(step);
          });
        observers.registration->AddObserver(
          itk::MultiResolutionIterationEvent(), level_start);

        auto level_end = itk::CStyleCommand::New();
        level_end->SetClientData(&observers);
        level_end->SetCallback(
          [](itk::Object *, const itk::EventObject &, void *data) {
            auto             *c = static_cast<LevelObservers *>(data);
            RegistrationLevel level;
            const std::size_t l   = c->levels->size();
            level.shrink_factor   = c->prm->shrink_factors[l];
            level.smoothing_sigma = c->prm->smoothing_sigmas[l];
            level.learning_rate   = level_learning_rate(*c->prm, l);
            level.iterations      = c->optimizer->GetCurrentIteration();
            level.metric          = c->optimizer->GetCurrentMetricValue();
            level.stop            = c->optimizer->GetStopConditionDescription();
            c->levels->push_back(level);
          });
        observers.optimizer->AddObserver(itk::EndEvent(), level_end);
      }

      /// The transform found, in the result's terms.
      void
      fill_motion(const Transform &transform, RegistrationResult &result)
      {
        const RigidTransform pre_to_post = rigid(transform);
        result.post_to_pre               = pre_to_post.inverse();
        const auto versor                = transform.GetVersor();
        result.versor                    = {
                             {versor.GetX(), versor.GetY(), versor.GetZ(), versor.GetW()}};
        for (unsigned int d = 0; d < 3; ++d)
          {
            result.centre[d]          = transform.GetCenter()[d];
            result.itk_translation[d] = transform.GetTranslation()[d];
          }
        result.angle_degrees = pre_to_post.angle_degrees();
      }
    } // namespace

    bool
    Box::empty() const
    {
      for (unsigned int d = 0; d < 3; ++d)
        if (!(upper[d] > lower[d]))
          return true;
      return false;
    }

    Vec3
    Box::centre() const
    {
      return {{0.5 * (lower[0] + upper[0]),
               0.5 * (lower[1] + upper[1]),
               0.5 * (lower[2] + upper[2])}};
    }

    RegistrationResult
    register_rigid(const CTVolume               &pre_operative,
                   const CTVolume               &post_operative,
                   const RegistrationParameters &prm)
    {
      check_volume(pre_operative, "pre-operative");
      check_volume(post_operative, "post-operative");
      const unsigned int coarsest = check_schedule(prm);
      RegistrationResult result;
      const auto         region =
        subvolume_region(pre_operative, prm, coarsest, result);
      try
        {
          const FloatImage::Pointer pre       = float_image(pre_operative);
          const FloatImage::Pointer post      = float_image(post_operative);
          auto                      transform = initial_transform(
            pre_operative, post_operative, pre, post, prm, result.subvolume);
          MaskImage::Pointer mask;
          auto               metric = make_metric(prm, pre, region, mask);
          auto               optimizer =
            make_optimizer(prm, make_scales(metric, result.subvolume));

          auto registration = Registration::New();
          registration->SetFixedImage(fixed_image(prm, pre, region));
          registration->SetMovingImage(post);
          registration->SetMetric(metric);
          registration->SetOptimizer(optimizer);
          registration->SetInitialTransform(transform);
          registration->InPlaceOn();
          set_schedule(*registration, prm, result.subvolume_voxels);
          LevelObservers observers{registration.GetPointer(),
                                   optimizer.GetPointer(),
                                   &prm,
                                   &result.levels};
          observe_levels(observers);
          registration->Update();
          result.metric = metric->GetValue();
          fill_motion(*transform, result);
        }
      catch (const itk::ExceptionObject &e)
        {
          throw Error(std::string("register: ITK's registration failed: ") +
                      e.GetDescription());
        }
      return result;
    }

    CTVolume
    resample(const CTVolume       &image,
             const RigidTransform &image_to_grid,
             const CTVolume       &grid,
             const double          outside)
    {
      check_volume(image, "resampled");
      // ITK's resampling maps output points to input points: the inverse.
      const RigidTransform        back   = image_to_grid.inverse();
      auto                        affine = Transform::New();
      Transform::MatrixType       m;
      Transform::OutputVectorType t;
      for (unsigned int i = 0; i < 3; ++i)
        {
          for (unsigned int j = 0; j < 3; ++j)
            m[i][j] = back.rotation[3 * i + j];
          t[i] = back.translation[i];
        }
      try
        {
          affine->SetMatrix(m, 1e-6);
          affine->SetTranslation(t);
          auto filter =
            itk::ResampleImageFilter<FloatImage, FloatImage, double>::New();
          filter->SetInput(float_image(image));
          filter->SetTransform(affine);
          filter->SetInterpolator(
            itk::LinearInterpolateImageFunction<FloatImage, double>::New());
          filter->SetDefaultPixelValue(outside);
          FloatImage::SizeType      size;
          FloatImage::SpacingType   spacing;
          FloatImage::PointType     origin;
          FloatImage::DirectionType direction;
          itk_grid_of<FloatImage>(grid, size, spacing, origin, direction);
          filter->SetSize(size);
          filter->SetOutputSpacing(spacing);
          filter->SetOutputOrigin(origin);
          filter->SetOutputDirection(direction);
          filter->Update();
          const Volume<float> values = from_itk<float>(filter->GetOutput());
          CTVolume            out;
          out.reinit_like(grid);
          for (std::size_t v = 0; v < out.n_voxels(); ++v)
            out.values[v] = static_cast<std::int16_t>(
              std::lround(std::clamp<double>(values.values[v], -32768, 32767)));
          return out;
        }
      catch (const itk::ExceptionObject &e)
        {
          throw Error(std::string("resample: ") + e.GetDescription());
        }
    }

    TriangleSurface
    transform_surface(const TriangleSurface &surface,
                      const RigidTransform  &transform)
    {
      TriangleSurface moved = surface;
      for (auto &x : moved.points)
        x = transform(x);
      return moved;
    }

    std::string
    registration_table(const RegistrationResult &r)
    {
      std::ostringstream s;
      s << std::setprecision(10);
      const auto row = [&s](const std::string &name, const auto &values) {
        s << name;
        for (const double v : values)
          s << ", " << v;
        s << '\n';
      };
      s << "# softface register: the post-operative CT rigidly registered to "
           "the pre-operative CT (Mattes mutual information)\n"
           "# x_pre = R x_post + t carries post-operative points into the "
           "pre-operative frame (R row by row)\n";
      row("rotation", r.post_to_pre.rotation);
      row("translation", r.post_to_pre.translation);
      row("angle_degrees", std::array<double, 1>{{r.angle_degrees}});
      row("axis", r.post_to_pre.axis());
      s << "# ITK's VersorRigid3DTransform, pre-operative to post-operative: "
           "x_post = V (x_pre - centre) + centre + itk_translation\n";
      row("centre", r.centre);
      row("versor", r.versor);
      row("itk_translation", r.itk_translation);
      s << "# Mattes mutual information at the result (ITK's sign: lower is "
           "better)\n";
      row("metric", std::array<double, 1>{{r.metric}});
      s << "# subvolume: the pre-operative voxels the metric saw, and the "
           "extent of their centres (mm)\n";
      s << "subvolume_voxels, " << r.subvolume_voxels[0] << ", "
        << r.subvolume_voxels[1] << ", " << r.subvolume_voxels[2] << '\n';
      row("subvolume_lower", r.subvolume.lower);
      row("subvolume_upper", r.subvolume.upper);
      s << "# level, shrink factor, smoothing sigma (mm), first step, "
           "iterations, metric, stop condition\n";
      for (std::size_t l = 0; l < r.levels.size(); ++l)
        {
          std::string stop = r.levels[l].stop;
          std::replace(stop.begin(), stop.end(), ',', ';');
          std::replace(stop.begin(), stop.end(), '\n', ' ');
          s << "level, " << l + 1 << ", " << r.levels[l].shrink_factor << ", "
            << r.levels[l].smoothing_sigma << ", " << r.levels[l].learning_rate
            << ", " << r.levels[l].iterations << ", " << r.levels[l].metric
            << ", " << stop << '\n';
        }
      return s.str();
    }
  } // namespace Patient
} // namespace softface
