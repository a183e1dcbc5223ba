// Segmentation of a head CT (patient, seed 3.1) with ITK: smoothing,
// thresholds, hole filling, connected components and a distance map split
// the volume into skin, fat, muscle, bone and internal soft tissue.

#include <softface/core/error.h>
#include <softface/patient/segmentation.h>

#include "itk_volume.h"

#include <itkBinaryFillholeImageFilter.h>
#include <itkBinaryThresholdImageFilter.h>
#include <itkConnectedComponentImageFilter.h>
#include <itkImage.h>
#include <itkRelabelComponentImageFilter.h>
#include <itkSignedMaurerDistanceMapImageFilter.h>
#include <itkSmoothingRecursiveGaussianImageFilter.h>
#include <itkTimeProbe.h>

#include <set>
#include <sstream>

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
    } // namespace

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
      MaskImage::Pointer body_mask = threshold(smoothed, prm.body_threshold);
      if (count(body_mask) == 0)
        fail("'Scene/Patient/Segmentation/Body threshold' (" +
             number(prm.body_threshold) + " HU) selects no voxel.");
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
      // the minimum volume are noise or streaks.
      const auto bone_mask = threshold(smoothed, prm.bone_threshold);
      {
        auto *bone = bone_mask->GetBufferPointer();
        for (std::size_t v = 0; v < n; ++v)
          bone[v] = (bone[v] && body_piece[v] == 1);
      }
      if (count(bone_mask) == 0)
        fail("'Scene/Patient/Segmentation/Bone threshold' (" +
             number(prm.bone_threshold) +
             " HU) selects no voxel inside the "
             "body.");
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

      LabelVolume &labels = result.labels;
      labels.reinit_like(ct);
      const float *hu = smoothed->GetBufferPointer();
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
              else if (hu[v] < prm.fat_threshold)
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
