"""A claim's outcome: the claim, its measured points and its assessment."""

from dataclasses import dataclass

from ..verdict import MEASURED, SKIPPED, UNFALSIFIABLE

__all__ = ["ClaimOutcome"]


@dataclass
class ClaimOutcome:
    """A claim together with its measured points and its assessment.

    Attributes
    ----------
    claim : Claim
    data : ClaimData
    assessment : Assessment
    mode : str
        The sweep mode (``"quick"`` or ``"full"``): which range and options were used.
    dimension : int or None
        Dimension of the claim's scene (2 or 3), when the engine lists it: claims of
        different dimensions never share a chart.
    """

    claim: object
    data: object
    assessment: object
    mode: str = "quick"
    dimension: object = None

    @property
    def agrees(self):
        """Whether the verdict is what the claims file expects.

        ``True`` for a reproduced claim expected to hold and a refuted claim expected
        not to hold, ``False`` for the opposite, ``None`` if inconclusive, unfalsifiable
        (a test that could not have failed decides nothing), skipped or measured (nothing
        published to agree with).
        """
        verdict = self.assessment.verdict
        if verdict in ("inconclusive", UNFALSIFIABLE, SKIPPED, MEASURED):
            return None
        return (verdict == "reproduced") == self.claim.expected_to_hold
