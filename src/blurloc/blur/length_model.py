"""The learnt length model: an ensemble of small perceptrons from blur features to blur extent,
its ``.npz`` file format, its fitting, and the model shipped with the package."""

from __future__ import annotations

import functools
import itertools
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..files import atomic_path
from .features import BlurFeatures

#: Length model shipped with the package: :func:`fit_length_model` on the training splits of
#: several stand-in renders and on blurred photographs (the recipe:
#: ``benchmarks/bench_blur_estimation.py``; notebook 01 refits it and compares).
LENGTH_MODEL_PATH = Path(__file__).parents[1] / "weights" / "blur_length.npz"


Layers = tuple[tuple[np.ndarray, np.ndarray], ...]


def _perceptron(layers: Layers, inputs: np.ndarray) -> np.ndarray:
    """Output (N,) of one tanh perceptron (each layer's weight (out, in) and bias (out,))."""
    hidden = inputs
    for number, (weight, bias) in enumerate(layers):
        hidden = hidden @ weight.T + bias
        if number < len(layers) - 1:
            hidden = np.tanh(hidden)
    return hidden[:, 0]


@dataclass(frozen=True)
class LengthModel:
    """Small multilayer perceptrons from :func:`blur_features` values to the blur extent (px at
    the analysis scale), averaged: standardised features, tanh hidden layers, one linear output.

    ``mean`` and ``spread`` (k,) standardise the features; ``members`` holds, for each
    perceptron, each layer's weight (out, in) and bias (out,).
    """

    mean: np.ndarray
    spread: np.ndarray
    members: tuple[Layers, ...]

    def predict(self, values: np.ndarray) -> np.ndarray:
        r"""Extents (N,) in px at the analysis scale: the mean of the members' outputs.

        .. math::

            \hat{L}(v) = \frac{1}{M} \sum_{m=1}^{M} f_m\!\left(\frac{v - \mu}{s}\right)

        for M perceptrons :math:`f_m` (tanh hidden layers, linear output) on features v
        standardised by ``mean`` :math:`\mu` and ``spread`` s.

        Parameters
        ----------
        values : numpy.ndarray
            Feature values (N, k) or (k,) (``BlurFeatures.values``).

        Returns
        -------
        numpy.ndarray
            (N,) extents, px at the analysis scale (not clipped at 0).

        References
        ----------
        Hornik, Stinchcombe and White, "Multilayer feedforward networks are universal
        approximators", Neural Networks 2(5), 1989. Lakshminarayanan, Pritzel and Blundell,
        "Simple and scalable predictive uncertainty estimation using deep ensembles", NeurIPS
        2017 (averaging networks trained from different initial weights).
        The paper's Section III.A.1 (the blur length of eq. 1's c, which it does not say how to
        estimate).
        """
        inputs = (np.atleast_2d(values) - self.mean) / self.spread
        return np.mean([_perceptron(layers, inputs) for layers in self.members], axis=0)

    def save(self, path: str | os.PathLike) -> None:
        """Write the model to an ``.npz`` file (plain arrays: ``mean``, ``spread`` and each member's
        ``member{m}_weight{n}`` and ``member{m}_bias{n}``).

        Parameters
        ----------
        path : str or os.PathLike
            The file to write, whole (write, then rename); ``.npz`` is added when missing.
        """
        arrays = {"mean": self.mean, "spread": self.spread}
        for member, layers in enumerate(self.members):
            for number, (weight, bias) in enumerate(layers):
                arrays[f"member{member}_weight{number}"] = weight
                arrays[f"member{member}_bias{number}"] = bias
        path = Path(path)
        if path.suffix != ".npz":
            path = path.with_name(path.name + ".npz")
        with atomic_path(path) as temporary, temporary.open("wb") as handle:
            np.savez(handle, **arrays)

    @classmethod
    def load(cls, path: str | os.PathLike) -> LengthModel:
        """Read a model written by :meth:`save` (arrays only; no pickles are loaded).

        Parameters
        ----------
        path : str or os.PathLike
            An ``.npz`` file written by :meth:`save`.

        Returns
        -------
        LengthModel
            The model.
        """
        with np.load(path) as arrays:
            names = arrays.files
            count = len({name.split("_")[0] for name in names if name.startswith("member")})
            members = []
            for member in range(count):
                depth = sum(name.startswith(f"member{member}_weight") for name in names)
                members.append(tuple((arrays[f"member{member}_weight{n}"],
                                      arrays[f"member{member}_bias{n}"])
                                     for n in range(depth)))  # fmt: skip
            return cls(arrays["mean"], arrays["spread"], tuple(members))


@functools.cache
def default_length_model() -> LengthModel:
    r"""The shipped length model (LENGTH_MODEL_PATH), read once per process.

    .. math::

        \hat{L}(v) = \frac{1}{M} \sum_{m=1}^{M} f_m\!\left(\frac{v - \mu}{s}\right)

    (:meth:`LengthModel.predict`), with the weights, :math:`\mu` and :math:`s` read from the file.

    Returns
    -------
    LengthModel
        The model that :func:`fit_length_model` fitted by the recipe of LENGTH_MODEL_PATH.

    References
    ----------
    See :func:`fit_length_model`. The paper's Section III.A.1 (the blur length of eq. 1's c,
    which it does not say how to estimate).
    """
    return LengthModel.load(LENGTH_MODEL_PATH)


def _fit_perceptron(
    inputs: np.ndarray,
    extents: np.ndarray,
    hidden: int,
    steps: int,
    weight_decay: float,
    seed: int,
) -> Layers:
    """One two-hidden-layer tanh perceptron fitted by full-batch Adam (least squares)."""
    import torch

    generator = torch.Generator().manual_seed(seed)
    sizes = (inputs.shape[1], hidden, hidden, 1)
    linear = [torch.nn.Linear(a, b) for a, b in itertools.pairwise(sizes)]
    with torch.no_grad():
        for layer in linear:  # PyTorch's default initialisation, drawn from our generator
            bound = 1.0 / np.sqrt(layer.in_features)
            layer.weight.uniform_(-bound, bound, generator=generator)
            layer.bias.uniform_(-bound, bound, generator=generator)
    network = torch.nn.Sequential(linear[0], torch.nn.Tanh(), linear[1], torch.nn.Tanh(),
                                  linear[2])  # fmt: skip
    inputs_t = torch.tensor(inputs, dtype=torch.float32)
    target = torch.tensor(extents, dtype=torch.float32)
    optimiser = torch.optim.Adam(network.parameters(), lr=1e-2, weight_decay=weight_decay)
    for _ in range(steps):
        optimiser.zero_grad()
        loss = ((network(inputs_t).squeeze(1) - target) ** 2).mean()
        loss.backward()
        optimiser.step()
    return tuple(
        (layer.weight.detach().numpy().astype(np.float64),
         layer.bias.detach().numpy().astype(np.float64))
        for layer in linear
    )  # fmt: skip


def fit_length_model(
    features: np.ndarray,
    extents_px: np.ndarray,
    hidden: int = 32,
    steps: int = 1000,
    weight_decay: float = 1e-3,
    seed: int = 0,
    members: int = 5,
) -> LengthModel:
    r"""Fit the length model: ``members`` two-hidden-layer tanh perceptrons, each by least
    squares with full-batch Adam from its own initial weights, whose outputs are averaged (a
    seed ensemble: one perceptron's estimates depend on its initial weights as much as the
    features allow, and the mean of several varies less).

    Each member minimises the mean squared error plus Adam's L2 term (λ = ``weight_decay``):

    .. math::

        \min_{\theta_m} \frac{1}{N} \sum_{i=1}^{N} (f_m(z_i; \theta_m) - L_i)^2
        + \frac{\lambda}{2} \|\theta_m\|^2, \qquad z_i = (v_i - \mu) / s

    Parameters
    ----------
    features : np.ndarray
        (N, k) feature values of N training frames (``BlurFeatures.values``).
    extents_px : np.ndarray
        (N,) recorded blur extents, px at the analysis scale (0 for sharp frames).
    hidden : int
        Units per hidden layer.
    steps : int
        Adam steps (learning rate 0.01) on the whole set.
    weight_decay : float
        L2 penalty on the weights (Adam's ``weight_decay``).
    seed : int
        Seed of the first member's initial weights (member m uses ``seed + m``).
    members : int
        Number of perceptrons averaged.

    Returns
    -------
    LengthModel
        The fitted model.

    Raises
    ------
    ValueError
        If the shapes do not match, N < 2, a value is not finite or ``members`` < 1.

    References
    ----------
    Hornik, Stinchcombe and White, "Multilayer feedforward networks are universal
    approximators", Neural Networks 2(5), 1989. Lakshminarayanan, Pritzel and Blundell,
    "Simple and scalable predictive uncertainty estimation using deep ensembles", NeurIPS
    2017 (averaging networks trained from different initial weights).
    Kingma and Ba, "Adam: a method for stochastic optimization", ICLR 2015.
    The paper's Section III.A.1 (the blur length of eq. 1's c, which it does not say how to
    estimate).
    """
    features = np.asarray(features, np.float64)
    extents = np.asarray(extents_px, np.float64)
    if features.ndim != 2 or len(features) != len(extents) or len(extents) < 2:
        raise ValueError("features must be (N, k) and extents (N,), N >= 2")
    if not (np.isfinite(features).all() and np.isfinite(extents).all()):
        raise ValueError("features and extents must be finite")
    if members < 1:
        raise ValueError(f"members must be >= 1, got {members}")
    mean, spread = features.mean(axis=0), features.std(axis=0) + 1e-9
    inputs = (features - mean) / spread
    fitted = tuple(_fit_perceptron(inputs, extents, hidden, steps, weight_decay, seed + member)
                   for member in range(members))  # fmt: skip
    return LengthModel(mean, spread, fitted)


def analysis_length(features: BlurFeatures, model: LengthModel | None = None) -> float:
    r"""Coarse blur length of an image at the analysis scale, by the length model.

    .. math::

        \hat{L} = \max(f_\theta(v), 0)

    with :math:`f_\theta` the model (:meth:`LengthModel.predict`) and v the feature values: px
    of the copy that :func:`~blurloc.blur.blur_features` measures (the image itself up to a short
    side of ANALYSIS_SIDE px, else the image area-averaged to it).

    Parameters
    ----------
    features : BlurFeatures
        :func:`~blurloc.blur.blur_features` of the image.
    model : LengthModel, optional
        Default: :func:`default_length_model`.

    Returns
    -------
    float
        Blur length, px at the analysis scale (>= 0).

    References
    ----------
    Hornik, Stinchcombe and White, "Multilayer feedforward networks are universal
    approximators", Neural Networks 2(5), 1989. Lakshminarayanan, Pritzel and Blundell,
    "Simple and scalable predictive uncertainty estimation using deep ensembles", NeurIPS
    2017 (averaging networks trained from different initial weights).
    The paper's Section III.A.1 (the blur length of eq. 1's c, which it does not say how to
    estimate).
    """
    model = model or default_length_model()
    return max(float(model.predict(features.values)[0]), 0.0)


def length_from_features(features: BlurFeatures, model: LengthModel | None = None) -> float:
    r"""Coarse blur length of an image from its features, in the image's pixels.

    .. math::

        L = s \cdot \hat{L}

    with :math:`\hat{L}` the length at the analysis scale (:func:`analysis_length`) and s the
    factor from analysis pixels to the image's pixels (``features.scale``).

    Parameters
    ----------
    features : BlurFeatures
        :func:`~blurloc.blur.blur_features` of the image.
    model : LengthModel, optional
        Default: :func:`default_length_model`.

    Returns
    -------
    float
        Blur length, px of the image the features came from (>= 0).

    References
    ----------
    See :func:`analysis_length`.
    The paper's Section III.A.1 (the blur length of eq. 1's c, which it does not say how to
    estimate).
    """
    return analysis_length(features, model) * features.scale
