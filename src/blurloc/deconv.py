"""Deconvolution: the inverse filter (eq. 3), the Wiener filter (eq. 4) and blind deblurring.

Boundaries: the DFT treats an image as periodic, so a real photograph's opposite edges, which
do not match, ring after deconvolution. Both filters therefore extend the image by mirror
reflection (by at least the kernel size) before the transform and crop the result back. A
blurred frame's border also holds light from outside the frame, which a mirror does not hold;
the Wiener filter can instead treat the image beyond the frame as unknown
(``boundary="unknown"``) and solve for it by conjugate gradients.
"""

from __future__ import annotations

import cv2
import numpy as np
import scipy.fft

from .blur import (
    BLUR_THRESHOLD,
    BlurEstimate,
    BlurFeatures,
    analysis_length,
    blur_features,
    check_kernel,
    estimate_motion_blur,
    estimate_noise_sigma,
    kernel_to_otf,
)
from .images import check_image

#: NSR = NSR_COEFFICIENT * sigma ** NSR_EXPONENT (sigma: the image's noise, [0, 1] scale): a
#: least-squares fit (in log) to the PSNR-best NSR of 192 blurred crops of scikit-image
#: photographs (sigma 0.0025-0.02, L 5-25 px). The best NSR hardly depends on the image's
#: variance or on L (fitted exponents -0.10 and -0.06), so they are left out.
NSR_COEFFICIENT = 0.59
NSR_EXPONENT = 0.72

#: How the NSR of eq. 4 depends on frequency (:func:`wiener_deconvolve`): ``"constant"``, one
#: NSR for every frequency, as eq. 4 is printed; ``"gradient"``, NSR(f) = lambda |D(f)|^2 with
#: |D(f)|^2 the squared response of the image's horizontal and vertical differences: a Tikhonov
#: filter with a first-difference penalty, the Wiener filter for a prior power spectrum
#: proportional to 1/|D(f)|^2 (about 1/|f|^2, a natural image's, at low frequencies), which
#: leaves the mean (f = 0) untouched where a constant NSR scales it by 1 / (1 + NSR).
REGULARISERS = ("constant", "gradient")
#: How :func:`wiener_deconvolve` treats the image beyond the frame: ``"mirror"``, a reflection of
#: the frame (one pass of eq. 4); ``"unknown"``, unknown pixels solved for together with the
#: frame, so that the light the blur carried into the frame from outside is explained by them.
BOUNDARIES = ("mirror", "unknown")
#: Conjugate-gradient iterations of the unknown-boundary solve, started from the mirror result
#: (chosen by ``benchmarks/motion_wiener_bounds.py``, its iterations table).
BOUNDARY_ITERATIONS = 10
#: Blind deblurring (:func:`deblur_blind`) restores with BLIND_REGULARISER; for the gradient
#: regulariser its weight is lambda = GRADIENT_WEIGHT_PER_NOISE * sigma (sigma: the frame's noise,
#: [0, 1] scale). Chosen with the gate below by ``benchmarks/choose_blind_gate.py`` (among eq. 4's
#: constant NSR and weights of 1-40 sigma).
BLIND_REGULARISER = "gradient"
GRADIENT_WEIGHT_PER_NOISE = 20.0

#: Blind deblurring restores a frame only where the frame itself says that the restoration is
#: likely to gain (:func:`blind_restoration_expected_to_gain`):
#:
#: - the length was refined from the spectrum's sinc zeros with a correlation of at least
#:   GATE_MIN_FIT: the blur is close to the straight line that eq. 4 is given (camera blur that
#:   turns or curves leaves no clear zeros, and deconvolving it by a line rings);
#: - the spectrum's fall-off depends on direction (anisotropy at least GATE_MIN_ANISOTROPY):
#:   the blur, not the scene, shapes the spectrum;
#: - the blur length at the analysis scale L is at least GATE_MIN_LENGTH * (sigma /
#:   GATE_REFERENCE_NOISE) ** GATE_NOISE_EXPONENT (sigma: the noise, [0, 1] scale; with the
#:   values below 3 px at sigma 0.01, 3.6 px at 0.02, 1.7 px at 0.001): the frequencies that
#:   deconvolution lifts must stand above the noise, and a short blur leaves little to recover
#:   while the filter still amplifies the noise;
#: - at most GATE_MAX_LENGTH: a long exposure's path is rarely one straight line;
#: - and the length refined from the sinc zeros is at most GATE_MAX_AGREEMENT times the coarse
#:   length of the length model (both in the image's pixels): a refined length well above the
#:   coarse one is the fit locking onto a multiple of the blur's zeros or onto the zeros of
#:   periodic content, and deconvolving by a kernel too long rings (infinite: no bound;
#:   ``benchmarks/choose_blind_gate.py`` grids it with the other thresholds).
#:
#: Chosen by ``benchmarks/choose_blind_gate.py``, together with the restoration above, on
#: scikit-image photographs blurred as a camera blurs them (sub-frames along shake paths, turned
#: about the centre, averaged in linear light, with and without noise) and on stand-in renders of
#: another seed (the largest mean PSNR change over a grid, the median over restored frames above
#: 0), and reported there on other photographs, on the stand-in and on real frames.
GATE_MIN_FIT = 0.6
GATE_MIN_ANISOTROPY = 0.5
GATE_MIN_LENGTH = 3.0
GATE_REFERENCE_NOISE = 0.01
GATE_NOISE_EXPONENT = 0.25
GATE_MAX_LENGTH = 20.0
GATE_MAX_AGREEMENT = 1.1


def estimate_nsr(image: np.ndarray) -> float:
    r"""Constant noise-to-signal ratio 1/SNR of eq. 4, from the image's noise level.

    .. math::

        \mathrm{NSR} = \max(a\, \sigma^{k}, 10^{-6})

    with :math:`a` = NSR_COEFFICIENT, :math:`k` = NSR_EXPONENT and :math:`\sigma` the noise
    standard deviation by Immerkær's method (:func:`~blurloc.blur.estimate_noise_sigma`).

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1].

    Returns
    -------
    float
        The NSR, > 0.

    References
    ----------
    Immerkær, "Fast noise variance estimation", CVIU 64(2), 1996. The paper's eq. 4.
    """
    return _nsr_from_noise(estimate_noise_sigma(image))


def _nsr_from_noise(sigma: float) -> float:
    """The NSR of :func:`estimate_nsr` for a noise sigma already measured."""
    return float(max(NSR_COEFFICIENT * sigma**NSR_EXPONENT, 1e-6))


def _even_dft_size(n: int) -> int:
    """Smallest even length >= ``n`` that OpenCV's DFT transforms fast (a product of 2, 3, 5)."""
    size = cv2.getOptimalDFTSize(n)
    while size % 2:
        size = cv2.getOptimalDFTSize(size + 1)
    return size


def ccs_pack(spectrum: np.ndarray) -> np.ndarray:
    """A real (M, N) array's ``rfft2`` spectrum (M, N/2 + 1) in OpenCV's packed CCS layout (M, N).

    The layout of ``cv2.dft`` on a real array, M and N even: column 0 and column N - 1 hold the
    zero and the Nyquist frequency column packed vertically (Re Y[0], Re Y[1], Im Y[1], ...,
    Re Y[M/2]); every other column pair (2k - 1, 2k) holds Re and Im of frequency column k.
    With it a frequency response computed in NumPy multiplies ``cv2.dft`` output directly
    (``cv2.mulSpectrums``).

    Parameters
    ----------
    spectrum : numpy.ndarray
        (M, N/2 + 1) complex, M even, N/2 + 1 >= 2.

    Returns
    -------
    numpy.ndarray
        (M, N) float32.

    Raises
    ------
    ValueError
        If M is odd or the spectrum has fewer than 2 columns.

    References
    ----------
    OpenCV documentation of ``cv::dft`` (CCS-packed output of real transforms).
    The paper's eq. 4 (computed with OpenCV's real DFT).
    """
    rows, half = spectrum.shape
    if rows % 2 or half < 2:
        raise ValueError(f"spectrum must be (M, N/2 + 1) with M even, got {spectrum.shape}")
    packed = np.empty((rows, 2 * (half - 1)), np.float32)
    packed[:, 1:-1:2] = spectrum[:, 1:-1].real
    packed[:, 2:-1:2] = spectrum[:, 1:-1].imag
    for column, source in ((0, 0), (-1, -1)):
        edge = spectrum[: rows // 2 + 1, source]
        packed[0, column] = edge[0].real
        packed[1:-1:2, column] = edge[1:-1].real
        packed[2:-1:2, column] = edge[1:-1].imag
        packed[-1, column] = edge[-1].real
    return packed


def _mirror_padded(image: np.ndarray, kernel: np.ndarray) -> tuple[np.ndarray, int]:
    """``image`` extended by mirror reflection by the kernel size plus 8 px on the top and left
    and up to an even, fast DFT size (:func:`_even_dft_size`) on the bottom and right, and the
    top-left margin (px)."""
    pad = max(kernel.shape) + 8
    height, width = image.shape[:2]
    shape = (_even_dft_size(height + 2 * pad), _even_dft_size(width + 2 * pad))
    padded = cv2.copyMakeBorder(image, pad, shape[0] - height - pad, pad, shape[1] - width - pad,
                                cv2.BORDER_REFLECT_101)  # fmt: skip
    return padded, pad


def _filter(image: np.ndarray, kernel: np.ndarray, response) -> np.ndarray:
    """Apply a frequency response (a function of the OTF) to each channel, with mirror padding.

    The response is computed once in NumPy's ``rfft2`` layout and packed for OpenCV
    (:func:`ccs_pack`); each channel then goes through ``cv2.dft``, ``cv2.mulSpectrums`` and
    ``cv2.idft`` in single precision (its 1e-7 relative error is far below 8-bit steps; on a
    640x480 RGB frame OpenCV's transforms take about half of SciPy's). ``image`` must be checked
    already (:func:`~blurloc.images.check_image`). Returns the input's dtype: uint8 rounded and
    clipped to 0-255 (the filter works on the 0-255 scale, so no rescaling is needed), float
    unclipped."""
    kernel = check_kernel(kernel, image.shape)
    padded, pad = _mirror_padded(image, kernel)
    height, width = image.shape[:2]
    gain = ccs_pack(response(kernel_to_otf(kernel, padded.shape[:2])))
    planes = cv2.split(padded) if image.ndim == 3 else [padded]
    restored = [
        cv2.idft(cv2.mulSpectrums(cv2.dft(np.float32(plane)), gain, 0),
                 flags=cv2.DFT_REAL_OUTPUT | cv2.DFT_SCALE)[pad : pad + height, pad : pad + width]
        for plane in planes
    ]  # fmt: skip
    if image.dtype == np.uint8:  # zero below 0, then round and saturate at 255
        restored = [cv2.convertScaleAbs(cv2.threshold(plane, 0.0, 0.0, cv2.THRESH_TOZERO)[1])
                    for plane in restored]  # fmt: skip
    result = cv2.merge(restored) if image.ndim == 3 else restored[0]
    return result if image.dtype == np.uint8 else result.astype(image.dtype)


def _unknown_boundary_filter(
    image: np.ndarray, kernel: np.ndarray, nsr: float, regulariser: str, iterations: int
) -> np.ndarray:
    """The least-squares problem of eq. 4 with the image beyond the frame unknown (see
    :func:`wiener_deconvolve`), solved by preconditioned conjugate gradients on all channels at
    once, in single precision; ``image`` checked already. Returns the input's dtype (uint8
    rounded and clipped, float unclipped).

    The iterates are kept as ``rfft2`` spectra: convolution, the regulariser and the
    preconditioner are then products, and each step needs two transforms (to apply the frame's
    mask); inner products are Parseval's, each half-spectrum coefficient counted for itself and
    its mirror (columns 0 and N/2 once)."""
    kernel = check_kernel(kernel, image.shape)
    height, width = image.shape[:2]
    planes = np.float32(image).reshape(height, width, -1)
    mirrored, pad = _mirror_padded(planes, kernel)
    shape = mirrored.shape[:2]
    otf = kernel_to_otf(kernel, shape)[..., None]
    penalty = np.full((shape[0], shape[1] // 2 + 1, 1), nsr, np.float32)
    if regulariser == "gradient":
        penalty = penalty * difference_power(shape)[..., None]
    circulant = otf.real**2 + otf.imag**2 + penalty  # eq. 4's denominator: the normal matrix, no M
    otf_conj = otf.conj()

    def forward(plane: np.ndarray) -> np.ndarray:
        return scipy.fft.rfft2(plane, axes=(0, 1))

    def inverse(spectrum: np.ndarray) -> np.ndarray:
        return scipy.fft.irfft2(spectrum, s=shape, axes=(0, 1))

    def inner(first: np.ndarray, second: np.ndarray) -> float:  # Parseval's, N even
        edges = np.vdot(first[:, 0], second[:, 0]) + np.vdot(first[:, -1], second[:, -1])
        return float(2.0 * np.vdot(first, second).real - edges.real)

    frame = np.s_[pad : pad + height, pad : pad + width]
    inside = np.zeros((*shape, 1), np.float32)
    inside[frame] = 1.0

    def normal(spectrum: np.ndarray) -> np.ndarray:  # (C^H M^T M C + penalty) x, as spectra
        return otf_conj * forward(inside * inverse(otf * spectrum)) + penalty * spectrum

    estimate = otf_conj * forward(mirrored.reshape(*shape, -1)) / circulant
    observed = np.zeros((*shape, planes.shape[2]), np.float32)
    observed[frame] = planes
    residual = otf_conj * forward(observed) - normal(estimate)
    step = residual / circulant
    direction = step
    alignment = inner(residual, step)
    for _ in range(iterations):
        if alignment == 0:  # solved exactly
            break
        image_of_direction = normal(direction)
        size = alignment / inner(direction, image_of_direction)
        estimate = estimate + size * direction
        residual = residual - size * image_of_direction
        step = residual / circulant
        alignment, previous = inner(residual, step), alignment
        direction = step + (alignment / previous) * direction
    restored = inverse(estimate)[frame].reshape(image.shape)
    if image.dtype == np.uint8:
        return np.uint8(np.clip(np.rint(restored), 0, 255))
    return restored.astype(image.dtype)


def check_boundary(boundary: str) -> None:
    """Refuse a boundary treatment that is not one of BOUNDARIES, naming it.

    Parameters
    ----------
    boundary : str
        ``"mirror"`` or ``"unknown"`` (:func:`wiener_deconvolve`).

    Raises
    ------
    ValueError
        If ``boundary`` is not in BOUNDARIES.
    """
    if boundary not in BOUNDARIES:
        raise ValueError(f"boundary must be one of {BOUNDARIES}, got {boundary!r}")


def _check_regulariser(regulariser: str) -> None:
    """Refuse a regulariser that is not one of REGULARISERS, naming it."""
    if regulariser not in REGULARISERS:
        raise ValueError(f"regulariser must be one of {REGULARISERS}, got {regulariser!r}")


def difference_power(shape: tuple[int, int]) -> np.ndarray:
    r"""Squared response of the horizontal and vertical first differences on a DFT grid.

    .. math::

        |D(u, v)|^2 = 4 \sin^2(\pi u / M) + 4 \sin^2(\pi v / N)

    Zero at the mean (u = v = 0), 8 at the highest frequency; the gradient regulariser of
    :func:`wiener_deconvolve` weighs the NSR by it.

    Parameters
    ----------
    shape : tuple of int
        (M, N) size of the transform.

    Returns
    -------
    numpy.ndarray
        (M, N // 2 + 1) float32, in the ``rfft2`` layout of :func:`kernel_to_otf`.

    References
    ----------
    Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Section 5.9
    (constrained least squares filtering).
    """
    rows = 4.0 * np.sin(np.pi * np.fft.fftfreq(shape[0]))[:, None] ** 2
    columns = 4.0 * np.sin(np.pi * np.fft.rfftfreq(shape[1]))[None, :] ** 2
    return (rows + columns).astype(np.float32)


def _wiener_response(otf: np.ndarray, nsr: float, regulariser: str = "constant") -> np.ndarray:
    """conj(C) / (|C|^2 + NSR(f)), the frequency response of eq. 4, in the OTF's precision."""
    weight = np.float32(nsr)
    if regulariser == "gradient":  # the rfft2 half (M, N/2 + 1) of an (M, N) grid, N even
        weight = weight * difference_power((otf.shape[0], 2 * (otf.shape[1] - 1)))
    return otf.conj() / (otf.real**2 + otf.imag**2 + weight)


def wiener_deconvolve(
    image: np.ndarray,
    kernel: np.ndarray,
    nsr: float | None = None,
    regulariser: str = "constant",
    boundary: str = "mirror",
    iterations: int = BOUNDARY_ITERATIONS,
) -> np.ndarray:
    r"""Wiener deconvolution (eq. 4) of each channel, with mirror-padded or unknown boundaries.

    .. math::

        \tilde{x} = F^{-1}\left\{ \frac{|F\{c\}|^2}{|F\{c\}|^2 + 1/\mathrm{SNR}}
        \cdot \frac{F\{b\}}{F\{c\}} \right\}
        = F^{-1}\left\{ \frac{\overline{F\{c\}}}{|F\{c\}|^2 + \mathrm{NSR}(f)}\,
        F\{b\} \right\}

    With NSR -> 0 it becomes the inverse filter (eq. 3). The NSR stands for the ratio of the
    noise's to the image's power spectral density, which eq. 4 assumes known per frequency. With
    ``regulariser="constant"`` (eq. 4 as the paper prints it) it is one number, so the mean
    intensity, where the kernel's response is 1, is scaled by 1 / (1 + NSR). With
    ``"gradient"`` it is :math:`\lambda |D(f)|^2` (:func:`difference_power`): the NSR of an
    image whose power spectrum is proportional to :math:`1/|D(f)|^2` (about :math:`1/|f|^2` at
    low frequencies; a Tikhonov filter with a first-difference penalty), zero at the mean, which
    is then kept.
    With ``boundary="mirror"`` the image is extended by mirror reflection (by the kernel size
    plus 8 px) before the DFT and cropped back, so that its non-matching opposite edges do not
    ring. A blurred frame's border, though, holds light that the blur carried in from beyond the
    frame, which no reflection holds. With ``boundary="unknown"`` the image x is solved for on
    the extended grid, the pixels beyond the frame unknown like the rest, and only the frame's
    own pixels are compared with the blur of x (M: the frame's mask, C: convolution by c,
    :math:`\Gamma`: the NSR's regulariser, :math:`\mathrm{NSR}\,|D|^2` or the constant NSR):

    .. math::

        \tilde{x} = \arg\min_x \|M(c * x) - b\|^2 + x^\top \Gamma x, \qquad
        (C^\top M^\top M C + \Gamma)\, \tilde{x} = C^\top M^\top b

    Without M this is eq. 4 itself; with it, the normal equations are solved by ``iterations``
    steps of conjugate gradients preconditioned by eq. 4's own filter
    :math:`(C^\top C + \Gamma)^{-1}` and started from the mirror result, on the iterates'
    spectra (2 transforms per step; the mirror filter needs 2 in all).

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) blurred image b, uint8 or float in [0, 1].
    kernel : numpy.ndarray
        (h, w) PSF c (normalised to sum 1 here), no larger than the image.
    nsr : float, optional
        The constant 1/SNR, or :math:`\lambda` for the gradient regulariser (> 0); default, for
        the constant NSR only, :func:`estimate_nsr` of the image (:func:`blind_nsr` gives the
        :math:`\lambda` that blind deblurring uses).
    regulariser : str
        ``"constant"`` or ``"gradient"`` (REGULARISERS).
    boundary : str
        ``"mirror"`` or ``"unknown"`` (BOUNDARIES).
    iterations : int
        Conjugate-gradient steps of the unknown-boundary solve (>= 0; 0 returns the mirror
        result).

    Returns
    -------
    numpy.ndarray
        The restored image, same shape; uint8 for uint8 input, else float64 (unclipped).

    Raises
    ------
    ValueError
        If ``nsr`` is not > 0 (or not given with the gradient regulariser), ``regulariser`` or
        ``boundary`` is unknown, ``iterations`` is negative, or the image or kernel is invalid.

    Examples
    --------
    >>> import numpy as np
    >>> from blurloc.blur import trajectory_kernel
    >>> kernel = trajectory_kernel(np.array([[-3.0, 0.0], [3.0, 0.0]]), origin=np.zeros(2))
    >>> frame = np.random.default_rng(0).random((60, 80, 3))
    >>> wiener_deconvolve(frame, kernel, nsr=0.02, regulariser="gradient",
    ...                   boundary="unknown").shape
    (60, 80, 3)

    References
    ----------
    Wiener, *Extrapolation, Interpolation, and Smoothing of Stationary Time Series*, MIT Press,
    1949. Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Sections 5.7-5.9
    (inverse, minimum mean square error and constrained least squares filtering). Field,
    "Relations between the statistics of natural images and the response properties of cortical
    cells", JOSA A 4(12), 1987 (power spectra of natural images fall as 1/f^2). Reeves, "Fast
    image restoration without boundary artifacts", IEEE Trans. Image Process. 14(10), 2005, and
    Almeida and Figueiredo, "Deconvolving images with unknown boundaries using the alternating
    direction method of multipliers", IEEE Trans. Image Process. 22(8), 2013 (unknown
    boundaries). The paper's eq. 4.
    """
    _check_regulariser(regulariser)
    check_boundary(boundary)
    if iterations < 0:
        raise ValueError(f"iterations must be >= 0, got {iterations}")
    image = check_image(image)
    if nsr is None and regulariser == "gradient":
        raise ValueError(
            "the gradient regulariser needs its weight: pass nsr (blind_nsr gives "
            "blind deblurring's)"
        )
    if nsr is None:
        nsr = estimate_nsr(image)
    if not np.isfinite(nsr) or nsr <= 0:
        raise ValueError(f"nsr must be > 0, got {nsr}")
    if boundary == "unknown":
        return _unknown_boundary_filter(image, kernel, nsr, regulariser, iterations)
    return _filter(image, kernel, lambda otf: _wiener_response(otf, nsr, regulariser))


def inverse_filter(image: np.ndarray, kernel: np.ndarray, threshold: float = 1e-3) -> np.ndarray:
    r"""Inverse filter (eq. 3) of each channel, with mirror-padded boundaries.

    .. math::

        \tilde{x} = F^{-1}\left\{ \frac{F\{b\}}{F\{c\}} \right\},
        \qquad \text{set to } 0 \text{ where } |F\{c\}| < \tau

    Near the kernel's zeros eq. 3 divides by (almost) zero: those frequencies, where
    :math:`|F\{c\}|` is below the threshold :math:`\tau`, are dropped. Elsewhere noise is
    amplified by :math:`1 / |F\{c\}|`, which is why eq. 4 damps it.

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) blurred image b, uint8 or float in [0, 1].
    kernel : numpy.ndarray
        (h, w) PSF c (normalised to sum 1 here), no larger than the image.
    threshold : float
        :math:`\tau` (> 0).

    Returns
    -------
    numpy.ndarray
        The restored image, same shape; uint8 for uint8 input, else float64 (unclipped).

    Raises
    ------
    ValueError
        If ``threshold`` is not > 0, or the image or kernel is invalid.

    References
    ----------
    Gonzalez and Woods, *Digital Image Processing*, 4th ed., Pearson, 2018, Sections 5.7-5.8
    (inverse and minimum mean square error filtering). The paper's eq. 3.
    """
    if threshold <= 0:
        raise ValueError("threshold must be > 0")

    def response(otf: np.ndarray) -> np.ndarray:
        safe = np.where(np.abs(otf) < threshold, 1.0, otf)
        return np.where(np.abs(otf) < threshold, 0.0, 1.0 / safe)

    return _filter(check_image(image), kernel, response)


def blind_restoration_expected_to_gain(
    estimate: BlurEstimate,
    features: BlurFeatures,
    noise_sigma: float,
    length: float | None = None,
) -> bool:
    r"""Whether blind Wiener deconvolution of a frame is expected to raise its PSNR, judged from
    the frame alone (see the GATE_* constants for the reasons):

    .. math::

        \rho \ge \rho_{\min}, \quad a \ge a_{\min}, \quad
        L_{\min} \left(\frac{\sigma}{\sigma_0}\right)^{k} \le L \le L_{\max}, \quad
        \hat{L} \le g_{\max}\, s L

    with :math:`\rho` the sinc fit's correlation (``estimate.fit``, 0 when the length was not
    refined from the sinc zeros), :math:`a` the features' anisotropy, :math:`\sigma` the noise
    sigma, :math:`L` the blur length at the analysis scale
    (:func:`~blurloc.blur.analysis_length`), :math:`\hat{L}` the estimate's length
    (``estimate.length_px``, refined from the sinc zeros) and :math:`s` the features' scale
    (image px per analysis px); :math:`\rho_{\min}` = GATE_MIN_FIT,
    :math:`a_{\min}` = GATE_MIN_ANISOTROPY, :math:`L_{\min}` = GATE_MIN_LENGTH,
    :math:`\sigma_0` = GATE_REFERENCE_NOISE, :math:`k` = GATE_NOISE_EXPONENT,
    :math:`L_{\max}` = GATE_MAX_LENGTH and :math:`g_{\max}` = GATE_MAX_AGREEMENT.

    Parameters
    ----------
    estimate : BlurEstimate
        The frame's blur estimate (:func:`~blurloc.blur.estimate_motion_blur`).
    features : BlurFeatures
        The frame's features (:func:`~blurloc.blur.blur_features`).
    noise_sigma : float
        The frame's noise sigma on the [0, 1] scale (:func:`~blurloc.blur.estimate_noise_sigma`).
    length : float, optional
        The blur length L at the analysis scale; default
        :func:`~blurloc.blur.analysis_length` of ``features``.

    Returns
    -------
    bool

    References
    ----------
    Oliveira, Figueiredo and Bioucas-Dias, "Blind estimation of motion blur parameters for image
    deconvolution", IbPRIA 2007 (a linear blur shows as clear sinc zeros in the spectrum).
    Boracchi and Foi, "Modeling the performance of image restoration from motion blur", IEEE
    Trans. Image Process. 21(8), 2012 (what restoration gains depends on the blur and the
    noise). Immerkær, "Fast noise variance estimation", CVIU 1996.
    Not in the paper, which applies eq. 4 to every frame (Section III.A.1).
    """
    length = analysis_length(features) if length is None else length
    return (
        estimate.fit >= GATE_MIN_FIT
        and estimate.length_px <= GATE_MAX_AGREEMENT * length * features.scale
        and _trusted_frame(features, noise_sigma, length)
    )


def _trusted_frame(features: BlurFeatures, noise_sigma: float, length: float | None) -> bool:
    """The part of :func:`blind_restoration_expected_to_gain` known before the estimate."""
    length = analysis_length(features) if length is None else length
    shortest = GATE_MIN_LENGTH * (noise_sigma / GATE_REFERENCE_NOISE) ** GATE_NOISE_EXPONENT
    return features.anisotropy >= GATE_MIN_ANISOTROPY and shortest <= length <= GATE_MAX_LENGTH


def blind_kernel(
    image: np.ndarray, threshold: float = BLUR_THRESHOLD, gated: bool = False
) -> np.ndarray | None:
    r"""The kernel that blind deblurring uses for an image, or None when no blur is detected.

    .. math::

        \hat{c} = \begin{cases} c_{\hat{L}, \hat{\theta}} & \hat{L}_{\text{coarse}} > t
        \text{ (and, with } \texttt{gated}\text{, a gain is expected)} \\
        \text{None} & \text{otherwise} \end{cases}

    The image is judged blurred when its coarse length estimate (the detector's score,
    :func:`~blurloc.blur.blur_score`) exceeds ``threshold``; then the linear kernel of
    :func:`~blurloc.blur.estimate_motion_blur` is returned, unless ``gated`` and the restoration
    is not expected to gain (:func:`blind_restoration_expected_to_gain`). The features are
    computed once for all steps.

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1]; short side >= 16 px.
    threshold : float
        Blur length (px at the analysis scale, as :func:`~blurloc.blur.blur_score`) above which
        the image counts as blurred.
    gated : bool
        Return None also where the restoration is not expected to gain.

    Returns
    -------
    numpy.ndarray or None
        The estimated PSF c of eq. 1, or None for an image judged sharp (or passed through).

    References
    ----------
    The paper's Section III.A.1 (estimate the blur, then eq. 4).
    """
    return _blind_estimate(image, threshold, gated)[0]


def _blind_estimate(
    image: np.ndarray, threshold: float, gated: bool
) -> tuple[np.ndarray | None, float | None]:
    """:func:`blind_kernel`'s kernel and the noise sigma it measured on the way (None if not)."""
    features = blur_features(image)  # checks the image
    length = analysis_length(features)
    if length <= threshold:
        return None, None
    if not gated:
        return estimate_motion_blur(image, features=features).kernel(), None
    noise_sigma = estimate_noise_sigma(image)
    if not _trusted_frame(features, noise_sigma, length):  # no need to refine the estimate
        return None, noise_sigma
    estimate = estimate_motion_blur(image, features=features)
    if not blind_restoration_expected_to_gain(estimate, features, noise_sigma, length):
        return None, noise_sigma
    return estimate.kernel(), noise_sigma


def blind_nsr(
    image: np.ndarray, regulariser: str = BLIND_REGULARISER, noise_sigma: float | None = None
) -> float:
    r"""The NSR that blind deblurring restores an image with: eq. 4's constant NSR
    (:func:`estimate_nsr`) or the gradient regulariser's weight.

    .. math::

        \lambda = \max(g\, \sigma, 10^{-6})

    for the gradient regulariser, with :math:`g` = GRADIENT_WEIGHT_PER_NOISE and :math:`\sigma`
    the image's noise sigma (:func:`~blurloc.blur.estimate_noise_sigma`).

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1].
    regulariser : str
        One of REGULARISERS; default BLIND_REGULARISER.
    noise_sigma : float, optional
        The image's noise sigma, when already measured.

    Returns
    -------
    float
        The NSR (constant) or weight (gradient), > 0.

    Raises
    ------
    ValueError
        If ``regulariser`` is not one of REGULARISERS.

    References
    ----------
    Immerkær, "Fast noise variance estimation", CVIU 64(2), 1996. The paper's eq. 4.
    """
    _check_regulariser(regulariser)
    sigma = estimate_noise_sigma(image) if noise_sigma is None else noise_sigma
    if regulariser == "constant":
        return _nsr_from_noise(sigma)
    return float(max(GRADIENT_WEIGHT_PER_NOISE * sigma, 1e-6))


def deblur_blind(
    image: np.ndarray,
    nsr: float | None = None,
    threshold: float = BLUR_THRESHOLD,
    gated: bool = True,
    regulariser: str = BLIND_REGULARISER,
) -> np.ndarray:
    r"""Blind deblurring of one image: detect the blur, estimate it, undo it by Wiener
    deconvolution (eq. 4, with the NSR that BLIND_REGULARISER makes depend on frequency).

    :func:`blind_kernel` detects the blur and estimates its length and angle from the spectrum;
    :func:`wiener_deconvolve` restores the image with that kernel:

    .. math::

        \tilde{x} = F^{-1}\left\{ \frac{\overline{F\{\hat{c}\}}}{|F\{\hat{c}\}|^2
        + \mathrm{NSR}(f)} \, F\{b\} \right\}

    with the constant NSR of :func:`estimate_nsr`, or, for the gradient regulariser,
    :math:`\mathrm{NSR}(f) = \lambda |D(f)|^2` with :math:`\lambda` =
    GRADIENT_WEIGHT_PER_NOISE times the image's noise sigma (:func:`blind_nsr`).

    An image judged sharp, or (with ``gated``, the default) one whose restoration is not
    expected to gain (:func:`blind_restoration_expected_to_gain`), is returned unchanged (as a
    copy).

    Parameters
    ----------
    image : numpy.ndarray
        (H, W) or (H, W, 3) image, uint8 or float in [0, 1]; short side >= 16 px.
    nsr : float, optional
        The constant 1/SNR, or the gradient regulariser's weight (> 0); default
        :func:`blind_nsr` of the image.
    threshold : float
        Blur length (px at the analysis scale, as :func:`~blurloc.blur.blur_score`) above which
        the image counts as blurred.
    gated : bool
        Pass through a frame whose restoration is not expected to gain.
    regulariser : str
        The NSR's dependence on frequency (:func:`wiener_deconvolve`); default
        BLIND_REGULARISER.

    Returns
    -------
    numpy.ndarray
        The restored image (or a copy of the input), same shape and dtype rules as
        :func:`wiener_deconvolve`.

    References
    ----------
    Wiener 1949; Gonzalez and Woods 2018 (see :func:`wiener_deconvolve`). The paper's Section
    III.A.1 and eq. 4.
    """
    _check_regulariser(regulariser)
    kernel, noise_sigma = _blind_estimate(image, threshold, gated)
    if kernel is None:
        return image.copy()
    if nsr is None:  # the noise measured on the way is not measured twice
        nsr = blind_nsr(image, regulariser, noise_sigma)
    return wiener_deconvolve(image, kernel, nsr, regulariser)
