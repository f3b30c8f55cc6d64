"""Acc/dec before interpolation (ADCBI): speed caps, look-ahead and profiles."""
