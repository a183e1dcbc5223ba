#ifndef softface_patient_itk_volume_h
#define softface_patient_itk_volume_h

// softface's plain Volume to and from an itk::Image, with the physical frame
// (origin, spacing, direction) carried over; private to source/patient/itk/.

#include <softface/patient/volume.h>

#include <itkImage.h>

#include <algorithm>

namespace softface
{
  namespace Patient
  {
    template <typename T>
    Volume<T>
    from_itk(const typename itk::Image<T, 3>::Pointer &image)
    {
      Volume<T>  volume;
      const auto size      = image->GetLargestPossibleRegion().GetSize();
      const auto spacing   = image->GetSpacing();
      const auto origin    = image->GetOrigin();
      const auto direction = image->GetDirection();
      for (unsigned int d = 0; d < 3; ++d)
        {
          volume.size[d]    = size[d];
          volume.spacing[d] = spacing[d];
          volume.origin[d]  = origin[d];
          for (unsigned int c = 0; c < 3; ++c)
            volume.direction[3 * d + c] = direction[d][c];
        }
      const T *data = image->GetBufferPointer();
      volume.values.assign(data, data + volume.n_voxels());
      return volume;
    }

    /// The sampling grid of @p volume (size and physical frame) in the
    /// types of the ITK image class @p Image.
    template <typename Image, typename T>
    void
    itk_grid_of(const Volume<T>               &volume,
                typename Image::SizeType      &size,
                typename Image::SpacingType   &spacing,
                typename Image::PointType     &origin,
                typename Image::DirectionType &direction)
    {
      for (unsigned int d = 0; d < 3; ++d)
        {
          size[d]    = volume.size[d];
          spacing[d] = volume.spacing[d];
          origin[d]  = volume.origin[d];
          for (unsigned int c = 0; c < 3; ++c)
            direction[d][c] = volume.direction[3 * d + c];
        }
    }

    template <typename T>
    typename itk::Image<T, 3>::Pointer
    to_itk(const Volume<T> &volume)
    {
      using Image                         = itk::Image<T, 3>;
      auto                          image = Image::New();
      typename Image::SizeType      size;
      typename Image::SpacingType   spacing;
      typename Image::PointType     origin;
      typename Image::DirectionType direction;
      itk_grid_of<Image>(volume, size, spacing, origin, direction);
      image->SetRegions(size);
      image->SetSpacing(spacing);
      image->SetOrigin(origin);
      image->SetDirection(direction);
      image->Allocate();
      std::copy(volume.values.begin(),
                volume.values.end(),
                image->GetBufferPointer());
      return image;
    }

  } // namespace Patient
} // namespace softface

#endif
