"""The learned relaxation-cost estimator Psi_G of SuReNav (Sec. IV-C.2): graph inputs, GatedGCN, GraphGPS stack."""
