"""Learning from PHAV: TSN and Cool-TSN in plain torch (``phav train``) and the
learnability check of ``phav-validate``. torch is imported only where a model is built."""
