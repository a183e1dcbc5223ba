// Segmentation of a head CT (patient; Mollemans et al. 2007, Sec. 3.1) with
// ITK: smoothing, thresholds, hole filling, connected components and a distance
// map split the volume into skin, fat, muscle, bone and internal soft tissue.

#include <softface/core/error.h>
#include <softface/patient/segmentation.h>

#include "itk_volume.h"

#include <itkBinaryFillholeImageFilter.h>
#include <itkBinaryThresholdImageFilter.h>
#include <itkConnectedComponentImageFilter.h>
#include <itkHistogram.h>
#include <itkImage.h>
#include <itkOtsuMultipleThresholdsCalculator.h>
#include <itkRelabelComponentImageFilter.h>
#include <itkSignedMaurerDistanceMapImageFilter.h>
#include <itkSmoothingRecursiveGaussianImageFilter.h>
#include <itkTimeProbe.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>
#include <vector>

namespace softface
{
  namespace Patient
  {
    namespace
    {
      using CTImage    = itk::Image<std::int16_t, 3>;
      using FloatImage = itk::Image<float, 3>;
      using MaskImage  = itk::Image<std::uint8_t, 3>;
      using CountImage = itk::Image<std::uint32_t, 3>;

      MaskImage::Pointer
      threshold(const FloatImage::Pointer &image, const double lower)
      {
        auto filter =
          itk::BinaryThresholdImageFilter<FloatImage, MaskImage>::New();
        filter->SetInput(image);
        filter->SetLowerThreshold(lower);
        filter->SetUpperThreshold(itk::NumericTraits<float>::max());
        filter->SetInsideValue(1);
        filter->SetOutsideValue(0);
        filter->Update();
        return filter->GetOutput();
      }

      // Connected components (face neighbours), largest first.
      CountImage::Pointer
      components(const MaskImage::Pointer &mask, const std::size_t min_voxels)
      {
        auto cc =
          itk::ConnectedComponentImageFilter<MaskImage, CountImage>::New();
        cc->SetInput(mask);
        cc->SetFullyConnected(false);
        auto relabel =
          itk::RelabelComponentImageFilter<CountImage, CountImage>::New();
        relabel->SetInput(cc->GetOutput());
        relabel->SetMinimumObjectSize(min_voxels);
        relabel->Update();
        return relabel->GetOutput();
      }

      std::size_t
      count(const MaskImage::Pointer &mask)
      {
        const auto *v = mask->GetBufferPointer();
        const auto  n = mask->GetLargestPossibleRegion().GetNumberOfPixels();
        std::size_t c = 0;
        for (std::size_t i = 0; i < n; ++i)
          c += v[i] != 0;
        return c;
      }
      std::string
      number(const double x)
      {
        std::ostringstream s;
        s << x;
        return s.str();
      }

      // Bins of the histograms an 'auto' threshold is chosen on: some ten
      // HU wide over a head CT's range, finer over the narrower ranges of
      // the body and the soft tissue; the peaks are located to a fraction
      // of a bin.
      constexpr unsigned int n_bins = 256;

      // The peak of counts[first, last): the fullest bin, refined by the
      // parabola through it and its neighbours (the counts are a smooth
      // bump there, and its top moves continuously with the data, not by
      // whole bins).
      double
      peak(const std::vector<double> &counts,
           const std::size_t          first,
           const std::size_t          last)
      {
        std::size_t top = first;
        for (std::size_t b = first; b < last; ++b)
          if (counts[b] > counts[top])
            top = b;
        double position = top + 0.5;
        if (top > first && top + 1 < last)
          {
            const double a = counts[top - 1], b = counts[top],
                         c         = counts[top + 1];
            const double curvature = a - 2. * b + c;
            if (curvature < 0.)
              position += std::clamp(0.5 * (a - c) / curvature, -0.5, 0.5);
          }
        return position;
      }

      /**
       * The threshold between the two classes of the @p values that
       * @p select picks: Otsu's threshold (ITK) on their histogram splits
       * them, and the threshold lies @p fraction of the way from the lower
       * class's peak to the upper's (the midpoint by default). @p where
       * names the parameter in the error when too few values are there.
       */
      template <typename Select>
      double
      automatic_threshold(const float       *values,
                          const std::size_t  n,
                          Select           &&select,
                          const std::string &where,
                          const double       fraction = 0.5)
      {
        double      low        = std::numeric_limits<double>::max();
        double      high       = std::numeric_limits<double>::lowest();
        std::size_t n_selected = 0;
        for (std::size_t v = 0; v < n; ++v)
          if (select(v))
            {
              low  = std::min<double>(low, values[v]);
              high = std::max<double>(high, values[v]);
              ++n_selected;
            }
        if (n_selected < 2 * n_bins || !(high > low))
          throw Error(where + " = auto: too few voxels with distinct values (" +
                      std::to_string(n_selected) +
                      ") to choose a threshold from; give a number.");
        const double        width = (high - low) / n_bins;
        std::vector<double> counts(n_bins, 0.);
        for (std::size_t v = 0; v < n; ++v)
          if (select(v))
            ++counts[std::min<std::size_t>(
              n_bins - 1, static_cast<std::size_t>((values[v] - low) / width))];

        using Histogram = itk::Statistics::Histogram<double>;
        auto histogram  = Histogram::New();
        histogram->SetMeasurementVectorSize(1);
        Histogram::SizeType size(1);
        size.Fill(n_bins);
        Histogram::MeasurementVectorType lower(1), upper(1);
        lower[0] = low;
        upper[0] = high;
        histogram->Initialize(size, lower, upper);
        for (unsigned int b = 0; b < n_bins; ++b)
          histogram->SetFrequency(b, counts[b]);
        auto otsu = itk::OtsuMultipleThresholdsCalculator<Histogram>::New();
        otsu->SetInputHistogram(histogram);
        otsu->SetNumberOfThresholds(1);
        otsu->Compute();
        // The peaks on the histogram smoothed over a few bins: the counts
        // of single bins are noisy (and combed when the scan's values are
        // coarser than a bin).
        std::vector<double> smooth(n_bins, 0.);
        for (int b = 0; b < int(n_bins); ++b)
          {
            double sum = 0., weight = 0.;
            for (int d = -3; d <= 3; ++d)
              if (b + d >= 0 && b + d < int(n_bins))
                {
                  const double w = std::exp(-0.5 * d * d);
                  sum += w * counts[b + d];
                  weight += w;
                }
            smooth[b] = sum / weight;
          }
        // The lower class: the bins up to Otsu's threshold (a bin's upper
        // end).
        const std::size_t split = std::clamp<std::size_t>(
          std::lround((otsu->GetOutput()[0] - low) / width), 1, n_bins - 1);
        const double lower_peak = peak(smooth, 0, split);
        const double upper_peak = peak(smooth, split, n_bins);
        return low +
               (lower_peak + fraction * (upper_peak - lower_peak)) * width;
      }
    } // namespace

    std::string
    describe_thresholds(const SegmentationParameters &prm,
                        const SegmentationResult     &result)
    {
      std::ostringstream s;
      s << std::fixed << std::setprecision(1);
      s << "body " << result.body_threshold
        << (prm.auto_body_threshold ? " (auto)" : "") << ", bone "
        << result.bone_threshold << (prm.auto_bone_threshold ? " (auto)" : "")
        << ", fat " << result.fat_threshold
        << (prm.auto_fat_threshold ? " (auto)" : "");
      return s.str();
    }

    SegmentationResult
    segment(const CTVolume               &ct,
            const SegmentationParameters &prm,
            const std::string            &source)
    {
      itk::TimeProbe clock;
      clock.Start();
      const auto fail = [&](const std::string &what) {
        std::ostringstream m;
        m << "Segmentation of '" << source << "': " << what;
        throw Error(m.str());
      };
      if (ct.n_voxels() == 0)
        fail("the volume is empty.");
      SegmentationResult result;
      const std::size_t  n = ct.n_voxels();

      FloatImage::Pointer smoothed;
      try
        {
          auto smoothing =
            itk::SmoothingRecursiveGaussianImageFilter<CTImage,
                                                       FloatImage>::New();
          smoothing->SetInput(to_itk(ct));
          smoothing->SetSigma(std::max(prm.smoothing, 1e-3));
          smoothing->Update();
          smoothed = smoothing->GetOutput();
        }
      catch (const itk::ExceptionObject &e)
        {
          fail(std::string("smoothing failed: ") + e.GetDescription());
        }

      // The body: above the body threshold, enclosed air filled, the
      // largest piece (the table and the scanner's air are not the head).
      const float      *hu     = smoothed->GetBufferPointer();
      const std::string where  = "Scene/Patient/Segmentation/";
      const auto        chosen = [&](const std::string &name) {
        return "Segmentation of '" + source + "': '" + where + name + "'";
      };
      // The body's threshold splits every voxel: air and the rest. A value
      // that fills over 1 % of the scan at its very bottom is the padding
      // outside the reconstructed field of view (-3024 or -2048 HU on many
      // scanners), not air: left out, lest Otsu split padding from air.
      result.body_threshold = prm.body_threshold;
      if (prm.auto_body_threshold)
        {
          const std::int16_t lowest =
            *std::min_element(ct.values.begin(), ct.values.end());
          const bool padded =
            std::count(ct.values.begin(), ct.values.end(), lowest) > n / 100;
          result.body_threshold = automatic_threshold(
            hu,
            n,
            [&](const std::size_t v) {
              return !padded || ct.values[v] != lowest;
            },
            chosen("Body threshold"));
        }
      MaskImage::Pointer body_mask = threshold(smoothed, result.body_threshold);
      if (count(body_mask) == 0)
        fail("'Scene/Patient/Segmentation/Body threshold' (" +
             number(result.body_threshold) +
             (prm.auto_body_threshold ? ", auto" : " HU") +
             ") selects no voxel.");
      {
        auto fill = itk::BinaryFillholeImageFilter<MaskImage>::New();
        fill->SetInput(body_mask);
        fill->SetForegroundValue(1);
        fill->SetFullyConnected(false);
        fill->Update();
        body_mask = fill->GetOutput();
      }
      const auto  body_pieces = components(body_mask, 1);
      const auto *body_piece  = body_pieces->GetBufferPointer();

      // Bone: above the bone threshold inside the body; pieces smaller than
      // the minimum volume are noise or streaks. An 'auto' bone threshold
      // splits the body's voxels above the body threshold (the enclosed air
      // left out): soft tissue and bone, 45 % of the way from the one's peak
      // to the other's, as the default lies on the phantom. Thin bone (a
      // skull a few voxels thick, the orbits' walls) never reaches the
      // bone's peak: at the midpoint the phantom's skull opens at 2 mm
      // voxels and the brain joins the facial soft tissue.
      result.bone_threshold =
        prm.auto_bone_threshold ?
          automatic_threshold(
            hu,
            n,
            [&](const std::size_t v) {
              return body_piece[v] == 1 && hu[v] >= result.body_threshold;
            },
            chosen("Bone threshold"),
            0.45) :
          prm.bone_threshold;
      const auto bone_mask = threshold(smoothed, result.bone_threshold);
      {
        auto *bone = bone_mask->GetBufferPointer();
        for (std::size_t v = 0; v < n; ++v)
          bone[v] = (bone[v] && body_piece[v] == 1);
      }
      if (count(bone_mask) == 0)
        fail("'Scene/Patient/Segmentation/Bone threshold' (" +
             number(result.bone_threshold) +
             (prm.auto_bone_threshold ? ", auto" : " HU") +
             ") selects no voxel inside the body.");
      const auto bone_pieces = components(
        bone_mask,
        std::max<std::size_t>(1, prm.min_bone_volume / ct.voxel_volume()));
      const auto *bone_piece = bone_pieces->GetBufferPointer();

      // Depth under the body surface (mm; negative inside).
      auto body_only = MaskImage::New();
      body_only->CopyInformation(body_mask);
      body_only->SetRegions(body_mask->GetLargestPossibleRegion());
      body_only->Allocate();
      for (std::size_t v = 0; v < n; ++v)
        body_only->GetBufferPointer()[v] = (body_piece[v] == 1);
      auto distance =
        itk::SignedMaurerDistanceMapImageFilter<MaskImage, FloatImage>::New();
      distance->SetInput(body_only);
      distance->SetInsideIsPositive(false);
      distance->SetUseImageSpacing(true);
      distance->SetSquaredDistance(false);
      distance->Update();
      const float *depth = distance->GetOutput()->GetBufferPointer();

      // Soft tissue, and which of it is external: connected to the skin.
      auto soft_mask = MaskImage::New();
      soft_mask->CopyInformation(body_mask);
      soft_mask->SetRegions(body_mask->GetLargestPossibleRegion());
      soft_mask->Allocate();
      auto *soft = soft_mask->GetBufferPointer();
      for (std::size_t v = 0; v < n; ++v)
        soft[v] = (body_piece[v] == 1 && bone_piece[v] == 0);
      const auto              soft_pieces = components(soft_mask, 1);
      const auto             *soft_piece  = soft_pieces->GetBufferPointer();
      std::set<std::uint32_t> external;
      for (std::size_t v = 0; v < n; ++v)
        if (soft_piece[v] != 0 && -depth[v] < prm.skin_thickness)
          external.insert(soft_piece[v]);

      // The fat's splits the tissue it decides on: the external soft
      // tissue deeper than the skin. Left out: the voxels within the skin
      // thickness of bone, whose values the bone's raise (on the phantom
      // they outnumber the fat and would split off as a class of their
      // own), and the air of the mouth and the airways, filled into the
      // body but neither fat nor muscle.
      result.fat_threshold = prm.fat_threshold;
      if (prm.auto_fat_threshold)
        {
          auto bone_only = MaskImage::New();
          bone_only->CopyInformation(body_mask);
          bone_only->SetRegions(body_mask->GetLargestPossibleRegion());
          bone_only->Allocate();
          for (std::size_t v = 0; v < n; ++v)
            bone_only->GetBufferPointer()[v] = (bone_piece[v] != 0);
          auto bone_distance =
            itk::SignedMaurerDistanceMapImageFilter<MaskImage,
                                                    FloatImage>::New();
          bone_distance->SetInput(bone_only);
          bone_distance->SetInsideIsPositive(false);
          bone_distance->SetUseImageSpacing(true);
          bone_distance->SetSquaredDistance(false);
          bone_distance->Update();
          const float *from_bone =
            bone_distance->GetOutput()->GetBufferPointer();
          std::vector<bool> is_external(n, false);
          for (std::size_t v = 0; v < n; ++v)
            is_external[v] =
              soft_piece[v] != 0 && external.count(soft_piece[v]);
          result.fat_threshold = automatic_threshold(
            hu,
            n,
            [&](const std::size_t v) {
              return is_external[v] && -depth[v] >= prm.skin_thickness &&
                     from_bone[v] >= prm.skin_thickness &&
                     hu[v] >= result.body_threshold &&
                     hu[v] < result.bone_threshold;
            },
            chosen("Fat threshold"));
        }

      LabelVolume &labels = result.labels;
      labels.reinit_like(ct);
      for (std::size_t v = 0; v < n; ++v)
        {
          std::uint8_t l = outside_body;
          if (bone_piece[v] != 0)
            l = bone_tissue;
          else if (soft_piece[v] != 0)
            {
              if (!external.count(soft_piece[v]))
                l = internal_tissue;
              else if (-depth[v] < prm.skin_thickness)
                l = skin_tissue;
              else if (hu[v] < result.fat_threshold)
                l = fat_tissue;
              else
                l = muscle_tissue;
            }
          labels.values[v] = l;
        }

      result.smoothed.reinit_like(ct);
      std::copy(hu, hu + n, result.smoothed.values.begin());
      clock.Stop();
      result.seconds = clock.GetTotal();
      return result;
    }
  } // namespace Patient
} // namespace softface
