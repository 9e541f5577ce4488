"""The numpy array types the cores are annotated with, by element type."""

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]  # coordinates, rays, speeds [SI units], points of a cloud
ByteArray = npt.NDArray[np.uint8]  # images: H x W x 3 (RGB) or H x W
